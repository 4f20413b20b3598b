/* case: loading, validating and resolving a case document. */
#include "input/case.h"

#include <libgen.h>
#include <string.h>

#include "util/yamldoc.h"

int case_load_file(struct case_doc *cd, const char *path, struct err *e)
{
    memset(cd, 0, sizeof *cd);
    snprintf(cd->name, sizeof cd->name, "%s", path);
    char tmp[4096];
    snprintf(tmp, sizeof tmp, "%s", path);
    snprintf(cd->dir, sizeof cd->dir, "%s", dirname(tmp));
    return yamldoc_load_file(path, &cd->doc, &cd->locs, e);
}

int case_load_json(struct case_doc *cd, const char *text, const char *name, struct err *e)
{
    memset(cd, 0, sizeof *cd);
    snprintf(cd->name, sizeof cd->name, "%s", name);
    snprintf(cd->dir, sizeof cd->dir, ".");
    json_error_t je;
    cd->doc = json_loads(text, JSON_REJECT_DUPLICATES, &je);
    if (!cd->doc)
        return err_set(e, ERR_INPUT, "%s:%d:%d: invalid JSON: %s", name, je.line, je.column,
                       je.text);
    return 0;
}

void case_doc_free(struct case_doc *cd)
{
    json_decref(cd->doc);
    locmap_destroy(&cd->locs);
    cd->doc = NULL;
}

int case_resolve(struct case_doc *cd, int shallow, int nthreads, const struct parallel *par,
                 struct case_resolved *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    struct cfg cfg = {cd->name, cd->locs, e, cd->dir, shallow};
    struct cfg_obj root;
    int rc = cfg_root(&cfg, cd->doc, &root);
    if (rc)
        return rc;
    const char *names[32];
    int n = 0;
    for (; case_types[n] && n < 31; n++)
        names[n] = case_types[n]->name;
    names[n] = NULL;
    int type;
    long seed;
    if ((rc = cfg_enum(&root, "type", "md", names, &type)) ||
        (rc = cfg_string(&root, "title", "", &out->common.title)) ||
        (rc = cfg_int(&root, "seed", 1, CFG_GE(0), &seed)) ||
        (rc = output_settings_read(&root, &out->output)) ||
        (rc = parallel_settings_read(&root, &out->common.parallel)))
        return rc;
    out->type = case_types[type];
    if (out->output.checkpoint_every > 0 && !out->type->checkpoints)
        return cfg_error_at(&cfg, "output.checkpoint_every",
                            "case type '%s' does not write checkpoints yet (it does not run on "
                            "the engine, engine/sim.h)",
                            out->type->name);
    /* a key that a case type would ignore is refused: the user asked for
     * moved faces and would get equal bricks without a word */
    if (out->common.parallel.balance != BALANCE_NONE && !out->type->balances)
        return cfg_error_at(&cfg, "parallel.balance",
                            "case type '%s' does not move its brick faces: balance: shift "
                            "runs with md, cluster_impact, dpd, mpm and the handshake cases "
                            "(docs/parallel.md); remove the key",
                            out->type->name);
    out->common.seed = (uint64_t)seed;
    out->common.nthreads = nthreads;
    out->common.par = par;
    rc = out->type->read(&root, &out->common, &out->state);
    if (!rc)
        rc = cfg_close(&root);
    if (rc)
        case_resolved_free(out);
    return rc;
}

void case_resolved_free(struct case_resolved *r)
{
    if (r->type && r->state)
        r->type->destroy(r->state);
    r->state = NULL;
}
