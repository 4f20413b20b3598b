/* cg_params: reading and writing the coarse-grained parameter file. */
#include "dpd/cg_params.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "util/cfg.h"
#include "util/wfile.h"
#include "util/yamldoc.h"

static int read_params(struct cfg_obj *o, struct cg_params *p)
{
    const char *element;
    int rc;
    if ((rc = cfg_string(o, "element", "Cu", &element)) ||
        (rc = cfg_real(o, "epsilon", CFG_REQUIRED, CFG_GT(0), &p->sc.eps)) ||
        (rc = cfg_real(o, "c", CFG_REQUIRED, CFG_GT(0), &p->sc.c)) ||
        (rc = cfg_real(o, "n", CFG_REQUIRED, CFG_RANGE(1, 60), &p->sc.n)) ||
        (rc = cfg_real(o, "m", CFG_REQUIRED, CFG_RANGE(1, 60), &p->sc.m)) ||
        (rc = cfg_real(o, "a", CFG_REQUIRED, CFG_GT(0), &p->sc.a)) ||
        (rc = cfg_real(o, "cutoff", CFG_REQUIRED, CFG_GT(0), &p->sc.rc)) ||
        (rc = cfg_real(o, "mass", CFG_REQUIRED, CFG_GT(0), &p->mass)) ||
        (rc = cfg_int(o, "atoms_per_particle", 1, CFG_RANGE(1, 1000000), &p->atoms_per_particle)) ||
        (rc = cfg_real(o, "lattice_constant", p->sc.a, CFG_GT(0), &p->lattice_constant)))
        return rc;
    cfg_allow(o, "fit");
    if ((rc = cfg_close(o)))
        return rc;
    if (strlen(element) >= sizeof p->element)
        return cfg_error_at(o->cfg, "element", "name longer than %zu characters",
                            sizeof p->element - 1);
    snprintf(p->element, sizeof p->element, "%s", element);
    if (!(p->sc.n > p->sc.m))
        return cfg_error_at(o->cfg, "n", "the repulsive exponent n = %g must exceed the density "
                                         "exponent m = %g", p->sc.n, p->sc.m);
    /* The cutoff must reach past the nearest neighbours of the fcc crystal
     * the parameters describe, or the crystal is not bound. */
    double rnn = p->lattice_constant / sqrt(2.0);
    if (!(p->sc.rc > 1.05 * rnn))
        return cfg_error_at(o->cfg, "cutoff",
                            "cutoff %g Å does not reach past the nearest-neighbour distance %g Å "
                            "of the fcc lattice (lattice_constant %g Å)",
                            p->sc.rc, rnn, p->lattice_constant);
    sc_params_finish(&p->sc);
    return 0;
}

int cg_params_load(const char *path, struct cg_params *out, struct err *e)
{
    memset(out, 0, sizeof *out);
    json_t *doc = NULL;
    struct locmap *locs = NULL;
    int rc = yamldoc_load_file(path, &doc, &locs, e);
    if (rc)
        return rc;
    struct cfg c = {path, locs, e, ".", 0};
    struct cfg_obj root;
    rc = cfg_root(&c, doc, &root);
    if (!rc)
        rc = read_params(&root, out);
    if (!rc)
        snprintf(out->source, sizeof out->source, "%s", path);
    json_decref(doc);
    locmap_destroy(&locs);
    return rc;
}

int cg_params_write(const char *path, const struct cg_params *prm, const char *header,
                    const json_t *fit, struct err *e)
{
    struct wfile w;
    int rc = wfile_open(&w, path, e);
    if (rc)
        return rc;
    FILE *f = w.f;
    if (header) {
        const char *s = header;
        while (*s) {
            size_t len = strcspn(s, "\n");
            fprintf(f, "# %.*s\n", (int)len, s);
            s += len + (s[len] == '\n');
        }
    }
    const struct sc_params *sc = &prm->sc;
    fprintf(f, "element: %s\n", prm->element);
    fprintf(f, "epsilon: %.10g          # eV\n", sc->eps);
    fprintf(f, "c: %.10g\n", sc->c);
    fprintf(f, "n: %.10g\n", sc->n);
    fprintf(f, "m: %.10g\n", sc->m);
    fprintf(f, "a: %.10g                # Å, length scale of the Sutton-Chen form\n", sc->a);
    fprintf(f, "cutoff: %.10g           # Å, shifted-force truncation\n", sc->rc);
    fprintf(f, "mass: %.10g             # amu per particle\n", prm->mass);
    fprintf(f, "atoms_per_particle: %ld\n", prm->atoms_per_particle);
    fprintf(f, "lattice_constant: %.10g # Å, fcc, at the fit temperature and zero pressure\n",
            prm->lattice_constant);
    if (fit && json_object_size(fit) > 0) {
        fprintf(f, "fit:\n");
        const char *key;
        json_t *val;
        /* sorted keys for a stable file */
        const char *keys[64];
        int nk = 0;
        json_object_foreach((json_t *)fit, key, val)
            if (nk < 64)
                keys[nk++] = key;
        for (int i = 1; i < nk; i++)
            for (int j = i; j > 0 && strcmp(keys[j - 1], keys[j]) > 0; j--) {
                const char *t = keys[j];
                keys[j] = keys[j - 1];
                keys[j - 1] = t;
            }
        for (int i = 0; i < nk; i++) {
            char *text = json_dumps(json_object_get(fit, keys[i]),
                                    JSON_COMPACT | JSON_ENCODE_ANY | JSON_REAL_PRECISION(10));
            int missing = !text;
            fprintf(f, "  %s: %s\n", keys[i], text ? text : "null");
            free(text);
            if (missing) {
                wfile_discard(&w);
                return err_set(e, ERR_RUNTIME, "cannot write %s: out of memory", path);
            }
        }
    }
    return wfile_commit(&w, e);
}
