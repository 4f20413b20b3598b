/* fuzz_result_json: a run directory's result.json as the campaign runner
 * reads it when the solver has exited (outcome_collect: status, message,
 * provenance, metrics, the files' hashes), for a clean exit and for exit 4
 * (diverged); the outcome then goes through the JSON message the MPI
 * workers send to rank 0 (outcome_to_json / outcome_from_json). */
#include "fuzz/common.h"
#include "fuzz/fuzz.h"

#include <stdlib.h>
#include <string.h>

#include "campaign/outcome.h"

static void collect(const char *dir, int exit_code)
{
    struct outcome o;
    memset(&o, 0, sizeof o);
    struct exit_info x = {exit_code << 8, 0, 0, 0.0, 0};
    outcome_collect(&o, dir, &x);
    json_t *j = outcome_to_json(&o);
    if (!j)
        abort();
    char *text = json_dumps(j, JSON_COMPACT);
    json_decref(j);
    if (!text)
        abort();
    json_t *back = json_loads(text, 0, NULL);
    free(text);
    struct outcome o2;
    struct err e = {0};
    /* the worker's message must carry the outcome (text that is not UTF-8
     * arrives with '?' in place of the bad bytes) */
    if (!back || outcome_from_json(&o2, back, &e) != 0 || o2.status != o.status ||
        strlen(o2.message) != strlen(o.message) || o2.nartifacts != o.nartifacts)
        abort();
    outcome_free(&o2);
    json_decref(back);
    outcome_free(&o);
}

int fuzz_result_json_one(const uint8_t *data, size_t size)
{
    char dir[FUZZ_PATH_MAX], path[FUZZ_PATH_MAX + 64];
    fuzz_dir_create(dir, sizeof dir);
    fuzz_write(dir, "result.json", data, size, path, sizeof path);
    fuzz_write(dir, "stderr", "error: fuzz\n", 12, path, sizeof path);
    collect(dir, 0);
    collect(dir, 4);
    fuzz_dir_remove(dir);
    return 0;
}

FUZZ_ENTRY(result_json)
