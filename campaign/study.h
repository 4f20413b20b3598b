/*
 * study: a study file (YAML) read and checked -- everything that can be
 * checked without the solver.  Expansion into jobs is plan.h.
 *
 *   name: md_timestep                  # [A-Za-z0-9_.-], names runs/<name>/
 *   description: free text
 *   base: case.yaml | {inline case}    # file names relative to the study file
 *   set: {md.steps: 200}               # fixed edits of the base (null deletes)
 *   sweep:
 *     grid: {md.timestep: [0.001, 0.002]}          # cartesian product
 *     zip:  {a.b: [1, 2], c.d: [3, 4]}             # one zipped factor, or a
 *                                                  # list of such mappings
 *   repeats: 3                         # seeds s0, s0+1, ... (s0: base seed or 1)
 *   prep:                              # preparation jobs; cases read their
 *     equil: {base: ..., set: {...}}   # outputs as ${prep.equil}/FILE
 *   metrics: [pe, temperature] | all
 *   series: [damage_eig_ratio]     result.json series to record in the database
 *                                  (table series_values; default none)
 *   launcher: local | "mpirun -np 4 [args]"
 *   threads: 1                         # --threads of each job
 *   timeout: 600                       # seconds per job (0: none)
 *   retries: 1                         # extra attempts after failed/crashed/timeout
 *   backend: local | slurm             # where jobs run (cascade run --backend overrides)
 *   max_running: 0                     # slurm: at most this many at once (0: no limit)
 *   slurm: {...}                       # Slurm resources (slurm_spec.h)
 *   report: {...}                      # report and regression settings (report_spec.h)
 *   refine: {...}                      # adaptive refinement (refine_spec.h)
 *   regress: {...}
 *
 * Every error names the file, line and column and the study key.
 */
#ifndef CASCADE_CAMPAIGN_STUDY_H
#define CASCADE_CAMPAIGN_STUDY_H

#include <jansson.h>
#include <stddef.h>

#include "docpath.h"
#include "refine_spec.h"
#include "report_spec.h"
#include "slurm_spec.h"
#include "util/err.h"
#include "util/locmap.h"

#define STUDY_PATH_MAX 4096
#define STUDY_WHERE_MAX 512
#define STUDY_NAME_MAX 128
#define STUDY_MAX_JOBS 10000000L

enum axis_kind { AXIS_GRID, AXIS_ZIP, AXIS_REPEAT };
enum study_backend { STUDY_BACKEND_LOCAL, STUDY_BACKEND_SLURM };

/* A case document and where it was written. */
struct study_source {
    json_t *doc;                   /* owned */
    struct locmap *locs;           /* owned when read from its own file, else NULL */
    char file[STUDY_PATH_MAX];     /* the file it was written in */
    char prefix[STUDY_WHERE_MAX];  /* its path inside that file ("" or "base", ...) */
    const struct locmap *view;     /* the locations of that file (borrowed or locs) */
};

struct study_setting {
    char path[DOCPATH_MAX];
    json_t *value;                 /* owned reference */
    char where[STUDY_WHERE_MAX];   /* study key, e.g. "set.md.steps" */
};

struct study_axis {
    char path[DOCPATH_MAX];
    enum axis_kind kind;
    int group;                     /* product factor, outermost first */
    json_t *values;                /* owned reference, a non-empty list */
    char where[STUDY_WHERE_MAX];   /* study key of the list */
};

struct study_prep {
    char name[64];
    struct study_source base;
    struct study_setting *set;
    int nset;
    char where[STUDY_WHERE_MAX];   /* "prep.NAME" */
};

struct study {
    char file[STUDY_PATH_MAX];     /* as given */
    char abspath[STUDY_PATH_MAX];
    char dir[STUDY_PATH_MAX];      /* absolute directory: jobs run from here */
    char *text;                    /* the file's bytes */
    size_t textlen;
    char hash[65];                 /* SHA-256 of text */
    json_t *doc;
    struct locmap *locs;

    char name[STUDY_NAME_MAX];
    char *description;
    struct study_source base;
    struct study_setting *set;
    int nset;
    struct study_axis *axes;
    int naxes;
    int ngroups;
    long *group_len;               /* values per factor */
    long repeats;
    struct study_prep *preps;      /* in dependency order (a prep reads only earlier ones) */
    int nprep;
    char **metrics;                /* NULL: all */
    int nmetrics;
    char **series;                 /* result.json series recorded in the database (NULL: none) */
    int nseries;
    char launcher[512];            /* "local" or the mpirun command as written */
    int mpirun_np;                 /* 0: local */
    long threads;
    double timeout;                /* seconds, 0: none */
    long retries;
    enum study_backend backend;
    long max_running;              /* slurm: jobs running at once, 0: no limit */
    struct slurm_spec slurm;       /* the `slurm` section */
    long njobs;                    /* sweep jobs (product of group_len) */
    struct report_spec report;     /* the `report` and `regress` sections */
    struct refine_spec refine;     /* the `refine` section (adaptive refinement) */
};

int study_load(struct study *s, const char *path, struct err *e);
void study_free(struct study *s);

/* "file:line:col" of a study key (or of its nearest written ancestor). */
void study_where(const struct study *s, const char *where, char *out, size_t len);
/* "file:line:col" of a case path inside a source. */
void study_source_where(const struct study *s, const struct study_source *src,
                        const char *case_path, char *out, size_t len);

/* The value indices of sweep job `seq` (one per group). */
void study_job_indices(const struct study *s, long seq, long *idx);

/* Build the case of sweep job `idx` (deep copy), or of prep `p` when idx is
 * NULL.  Errors name the study key. */
int study_job_doc(const struct study *s, int prep, const long *idx, json_t **doc, struct err *e);
/* The swept values of a sweep job as {axis: value} (new reference). */
json_t *study_job_params(const struct study *s, const long *idx);

/* The prep index of a name, or -1. */
int study_prep_index(const struct study *s, const char *name);

#endif
