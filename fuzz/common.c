/* common: scratch files and potentials for the fuzz harnesses (see common.h). */
#include "fuzz/common.h"

#include <dirent.h>
#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/neighbor.h"
#include "core/particles.h"
#include "md/potential.h"
#include "util/cfg.h"

void fuzz_dir_create(char *dir, size_t len)
{
    const char *tmp = getenv("TMPDIR");
    snprintf(dir, len, "%s/cascade-fuzz-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(dir)) {
        perror("fuzz: mkdtemp");
        abort();
    }
}

void fuzz_dir_remove(const char *dir)
{
    DIR *d = opendir(dir);
    if (d) {
        struct dirent *de;
        while ((de = readdir(d))) {
            if (strcmp(de->d_name, ".") == 0 || strcmp(de->d_name, "..") == 0)
                continue;
            char path[FUZZ_PATH_MAX + 256];
            snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
            unlink(path);
        }
        closedir(d);
    }
    rmdir(dir);
}

void fuzz_write(const char *dir, const char *name, const void *data, size_t size, char *path,
                size_t len)
{
    snprintf(path, len, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || (size && fwrite(data, 1, size, f) != size) || fclose(f) != 0) {
        perror("fuzz: writing the input");
        abort();
    }
}

char *fuzz_text(const uint8_t *data, size_t size)
{
    char *t = malloc(size + 1);
    if (!t)
        abort();
    if (size)
        memcpy(t, data, size);
    t[size] = '\0';
    return t;
}

void fuzz_check_error(int rc, const char *msg)
{
    if (rc && getenv("CASCADE_FUZZ_VERBOSE"))
        fprintf(stderr, "fuzz: rejected (%d): %s\n", rc, msg);
    if (rc && !msg[0]) {
        fprintf(stderr, "fuzz: the reader failed (%d) without a message\n", rc);
        abort();
    }
}

/* Atoms at plausible distances (0.9 to 6.6 Å): a file's tables are used the
 * way a run would use them, whatever their grid. */
static const double cluster[][3] = {
    {0.0, 0.0, 0.0}, {2.55, 0.0, 0.0}, {0.0, 1.8, 0.0},
    {1.3, 1.2, 1.9}, {0.5, 0.4, 0.6}, {4.4, 3.1, 2.0},
};

static void evaluate(struct potential *pot)
{
    struct err e = {0};
    struct particles *p = particles_create(8);
    if (!p)
        abort();
    int types[PARTICLES_MAX_TYPES];
    for (int k = 0; k < pot->nelements; k++)
        types[k] = particles_type_index(p, pot->element[k], 0);
    int n = (int)(sizeof cluster / sizeof *cluster);
    for (int i = 0; i < n; i++)
        if (particles_add(p, cluster[i], NULL, types[i % pot->nelements], i + 1) < 0)
            abort();
    int rc = potential_bind(pot, p, &e);
    fuzz_check_error(rc, e.msg);
    if (!rc) {
        struct nlist *nl = nlist_create(pot->list_kind, pot->cutoff, 0.0);
        if (!nl)
            abort();
        rc = nlist_build_brute(nl, p, &e);
        if (!rc) {
            struct force_result res;
            rc = pot->ops->compute(pot, p, nl, POT_PERATOM, &res, &e);
        }
        fuzz_check_error(rc, e.msg);
        nlist_destroy(&nl);
    }
    particles_destroy(&p);
}

void fuzz_potential(const char *style, const char *path, const char *const *elements,
                    const double *masses, int nelements)
{
    json_t *doc = json_pack("{s:s, s:s}", "style", style, "file", path);
    if (!doc)
        abort();
    if (nelements > 0) {
        json_t *list = json_array();
        for (int k = 0; k < nelements; k++)
            json_array_append_new(list, json_string(elements[k]));
        json_object_set_new(doc, "elements", list);
    }
    if (nelements > 0 && masses) {
        json_t *list = json_array();
        for (int k = 0; k < nelements; k++)
            json_array_append_new(list, json_real(masses[k]));
        json_object_set_new(doc, "masses", list);
    }
    struct err e = {0};
    struct cfg c = {"<fuzz>", NULL, &e, ".", 0};
    struct cfg_obj root;
    struct potential *pot = NULL;
    int rc = cfg_root(&c, doc, &root);
    if (!rc)
        rc = potential_create(&root, &pot);
    fuzz_check_error(rc, e.msg);
    if (!rc && pot)
        evaluate(pot);
    potential_destroy(&pot);
    json_decref(doc);
}
