/* fuzz_study: study files as `cascade plan|run` reads them (study_load),
 * with a case file `case.yaml` beside the study for `base: case.yaml`; a
 * study that loads builds the case documents of its preparation jobs and of
 * its first and last sweep jobs, as the planner does. */
#include "fuzz/common.h"
#include "fuzz/fuzz.h"

#include <stdlib.h>

#include "campaign/study.h"

static const char base_case[] =
    "title: fuzz base case\n"
    "system:\n"
    "  lattice: {style: fcc, a: 3.615, cells: [2, 2, 2]}\n"
    "  element: Cu\n"
    "potential: {style: sutton_chen}\n"
    "md: {timestep: 0.001, steps: 10}\n"
    "output: {hdf5: false}\n";

static void job(const struct study *s, int prep, const long *idx)
{
    struct err e = {0};
    json_t *doc = NULL;
    int rc = study_job_doc(s, prep, idx, &doc, &e);
    fuzz_check_error(rc, e.msg);
    json_decref(doc);
    if (idx)
        json_decref(study_job_params(s, idx));
}

int fuzz_study_one(const uint8_t *data, size_t size)
{
    char dir[FUZZ_PATH_MAX], path[FUZZ_PATH_MAX + 64], cpath[FUZZ_PATH_MAX + 64];
    fuzz_dir_create(dir, sizeof dir);
    fuzz_write(dir, "case.yaml", base_case, sizeof base_case - 1, cpath, sizeof cpath);
    fuzz_write(dir, "study.yaml", data, size, path, sizeof path);
    struct err e = {0};
    struct study s;
    int rc = study_load(&s, path, &e);
    fuzz_check_error(rc, e.msg);
    if (!rc) {
        for (int p = 0; p < s.nprep; p++)
            job(&s, p, NULL);
        long *idx = calloc((size_t)s.ngroups + 1, sizeof *idx);
        if (!idx)
            abort();
        if (s.njobs > 0) {
            study_job_indices(&s, 0, idx);
            job(&s, -1, idx);
            study_job_indices(&s, s.njobs - 1, idx);
            job(&s, -1, idx);
        }
        free(idx);
        char where[STUDY_PATH_MAX + 64];
        study_where(&s, "sweep", where, sizeof where);
        study_free(&s);
    }
    fuzz_dir_remove(dir);
    return 0;
}

FUZZ_ENTRY(study)
