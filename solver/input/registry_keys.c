/* registry_keys: the keys of every registry entry (see registry_keys.h). */
#include "input/registry_keys.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "md/potential.h"
#include "mpm/mpm_material.h"
#include "mpm/mpm_units.h"
#include "output/run.h"
#include "scenarios/case_type.h"
#include "util/cfg.h"

/* A describe read of `doc` (a shallow one: no file is opened, no model
 * built).  Keys a reader asks for after a check that the stand-in values
 * cannot pass are not listed; *note then says why. */
struct describe {
    struct err e;
    struct cfg c;
    struct cfg_obj root;
};

static int describe_open(struct describe *d, json_t *doc)
{
    memset(d, 0, sizeof *d);
    d->c = (struct cfg){"(info)", NULL, &d->e, ".", CFG_DESCRIBE};
    return cfg_root(&d->c, doc, &d->root);
}

/* The tree the reader left, with rc's message when it stopped early. */
static json_t *keys_of(json_t *doc, int rc, const struct describe *d)
{
    if (rc)
        json_object_set_new(doc, "(listing stopped)", json_string(d->e.msg));
    return doc;
}

/* A few checks across keys (a lattice or a file to read, a_max above
 * a_min, a stable Poisson ratio) reject any stand-in value; when the plain
 * listing stops at one, it is read again with these values given, and a
 * key of them keeps what the plain listing said of it ("(required)" or its
 * default).  A section of them that the entry does not read is left out. */
static const char *const case_seeds[] = {
    "{\"system\": {\"lattice\": {\"style\": \"fcc\", \"a\": 3.615, \"cells\": [4, 4, 4]},"
    " \"element\": \"Cu\"}, \"crystal\": {\"a_min\": 3.4, \"a_max\": 3.8}}",
    /* a flyer or a rod needs a free x boundary; a fit needs its points */
    "{\"system\": {\"lattice\": {\"style\": \"fcc\", \"a\": 3.615, \"cells\": [4, 4, 4]},"
    " \"element\": \"Cu\", \"boundary\": [\"free\", \"periodic\", \"periodic\"]},"
    " \"isotherm\": {\"densities\": [8.9, 9.5], \"pressures\": [0.0, 10.0]}}",
    /* the concurrent model's DPD and MPM ranges must not overlap */
    "{\"system\": {\"lattice\": {\"style\": \"fcc\", \"a\": 3.615, \"cells\": [4, 4, 4]},"
    " \"element\": \"Cu\", \"boundary\": [\"free\", \"periodic\", \"periodic\"]},"
    " \"concurrent\": {\"dpd\": [0.0, 10.0], \"mpm\": [10.0, 20.0]}}",
    NULL};
static const char *const material_seeds[] = {
    "{\"name\": \"m\", \"density\": 8.9, \"E\": 120.0, \"nu\": 0.3}",
    "{\"name\": \"m\", \"density\": 8.9, \"C11\": 170.0, \"C12\": 120.0, \"C44\": 75.0}",
    NULL};
static const char *const potential_seeds[] = {"{\"elements\": [\"Si\"]}", NULL};

/* Keys given by the seed take what the plain listing `first` said of them,
 * or "(required)" when it stopped before them (every seeded key is a
 * required one); a top-level one the entry did not read is dropped. */
static void unseed(json_t *tree, const json_t *seed, const json_t *first, int top)
{
    const char *k;
    json_t *sv;
    json_object_foreach((json_t *)seed, k, sv)
    {
        json_t *tv = json_object_get(tree, k), *fv = first ? json_object_get(first, k) : NULL;
        if (!tv)
            continue;
        if (top && !fv && json_equal(tv, sv))
            json_object_del(tree, k);   /* not read: not a key of this entry */
        else if (json_is_object(sv) && json_is_object(tv))
            unseed(tv, sv, json_is_object(fv) ? fv : NULL, 0);
        else if (fv && !json_is_object(fv))
            json_object_set(tree, k, fv);
        else
            json_object_set_new(tree, k, json_string(CFG_REQUIRED_MARK));
    }
}

/* The listing of an entry by `read` (which returns an err code): the plain
 * one, or the first that one of `seeds` completes, or else the plain one
 * with the reason it stopped. */
static json_t *listing(json_t *(*make)(const void *), const void *entry,
                       int (*read)(const void *, struct describe *), const char *const *seeds)
{
    json_t *doc = make(entry);
    struct describe d;
    int rc = describe_open(&d, doc);
    if (!rc)
        rc = read(entry, &d);
    for (int k = 0; rc && seeds[k]; k++) {
        json_t *seed = json_loads(seeds[k], 0, NULL);
        json_t *doc2 = make(entry);
        json_t *given = json_deep_copy(seed);   /* the reader edits what it is given */
        json_object_update_missing(doc2, given);
        json_decref(given);
        struct describe d2;
        int rc2 = describe_open(&d2, doc2);
        if (!rc2)
            rc2 = read(entry, &d2);
        if (!rc2) {
            unseed(doc2, seed, doc, 1);
            json_decref(seed);
            json_decref(doc);
            return doc2;
        }
        json_decref(seed);
        json_decref(doc2);
    }
    return keys_of(doc, rc, &d);
}

static const char *const common_keys[] = {"type", "title", "seed", "output", NULL};

static json_t *make_case(const void *entry)
{
    return json_pack("{s:s}", "type", ((const struct case_type *)entry)->name);
}

static int read_case(const void *entry, struct describe *d)
{
    const struct case_type *t = entry;
    const char *title = "";
    long seed;
    struct output_settings out;
    cfg_allow(&d->root, "type");
    int rc = cfg_string(&d->root, "title", "", &title);
    if (!rc)
        rc = cfg_int(&d->root, "seed", 1, CFG_GE(0), &seed);
    if (!rc)
        rc = output_settings_read(&d->root, &out);
    struct case_common cc = {.seed = 1, .title = title, .nthreads = 1};
    void *state = NULL;
    if (!rc)
        rc = t->read(&d->root, &cc, &state);
    if (state)
        t->destroy(state);
    return rc;
}

static json_t *make_potential(const void *entry)
{
    return json_pack("{s:s}", "style", ((const struct potential_style *)entry)->name);
}

static int read_potential(const void *entry, struct describe *d)
{
    (void)entry;
    struct potential *pot = NULL;
    int rc = potential_create(&d->root, &pot);
    potential_destroy(&pot);
    return rc;
}

static json_t *make_material(const void *entry)
{
    return json_pack("{s:s}", "law", ((const struct mpm_material_style *)entry)->law);
}

static int read_material(const void *entry, struct describe *d)
{
    (void)entry;
    struct mpm_units u;
    mpm_units_init(&u, MPM_UNITS_METAL);
    struct mpm_material *m = NULL;
    int rc = mpm_material_create(&d->root, &u, &m);
    free(m);
    return rc;
}

json_t *registry_keys_json(void)
{
    json_t *all = json_object(), *common = json_object(), *types = json_object(),
           *pots = json_object(), *mats = json_object();
    if (!all || !common || !types || !pots || !mats) {
        json_decref(all);
        json_decref(common);
        json_decref(types);
        json_decref(pots);
        json_decref(mats);
        return NULL;
    }
    for (int i = 0; case_types[i]; i++) {
        json_t *tree = listing(make_case, case_types[i], read_case, case_seeds);
        /* title, seed and output are every case's: listed once */
        for (int c = 0; common_keys[c]; c++) {
            if (json_object_size(common) < 4 && json_object_get(tree, common_keys[c]))
                json_object_set(common, common_keys[c], json_object_get(tree, common_keys[c]));
            json_object_del(tree, common_keys[c]);
        }
        json_object_set_new(types, case_types[i]->name, tree);
    }
    json_object_del(common, "type");
    for (int i = 0; potential_styles[i].name; i++)
        json_object_set_new(pots, potential_styles[i].name,
                            listing(make_potential, &potential_styles[i], read_potential,
                                    potential_seeds));
    for (int i = 0; mpm_material_styles[i].law; i++)
        json_object_set_new(mats, mpm_material_styles[i].law,
                            listing(make_material, &mpm_material_styles[i], read_material,
                                    material_seeds));
    json_object_set_new(all, "common", common);
    json_object_set_new(all, "case_types", types);
    json_object_set_new(all, "potential_styles", pots);
    json_object_set_new(all, "mpm_materials", mats);
    return all;
}
