/* potential: creation by style name, type mapping, file lookup. */
#include "md/potential.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int potential_create(struct cfg_obj *o, struct potential **out)
{
    const char *names[32];
    int n = 0;
    for (; potential_styles[n].name && n < 31; n++)
        names[n] = potential_styles[n].name;
    names[n] = NULL;
    int style;
    int rc = cfg_enum(o, "style", NULL, names, &style);
    if (rc)
        return rc;
    *out = NULL;
    rc = potential_styles[style].create(o, out);
    if (rc)
        return rc;
    if (*out)
        (*out)->nthreads = 1;
    rc = cfg_close(o);
    if (rc)
        potential_destroy(out);
    return rc;
}

void potential_destroy(struct potential **pot)
{
    if (pot && *pot) {
        (*pot)->ops->destroy(*pot);
        *pot = NULL;
    }
}

int potential_bind(struct potential *pot, struct particles *p, struct err *e)
{
    int *map = pot->type_map;
    for (int t = 0; t < p->ntypes; t++) {
        map[t] = -1;
        for (int k = 0; k < pot->nelements; k++)
            if (strcmp(pot->element[k], p->type_name[t]) == 0)
                map[t] = k;
        if (map[t] < 0) {
            char list[256] = "";
            for (int k = 0; k < pot->nelements; k++) {
                strncat(list, k ? ", " : "", sizeof list - strlen(list) - 1);
                strncat(list, pot->element[k], sizeof list - strlen(list) - 1);
            }
            return err_set(e, ERR_INPUT,
                           "particle type '%s' is not an element of the %s potential (it has: %s)",
                           p->type_name[t], pot->ops->style, list);
        }
        if (!(p->mass[t] > 0))
            p->mass[t] = pot->mass[map[t]];
        if (!(p->mass[t] > 0))
            return err_set(e, ERR_INPUT, "no mass known for particle type '%s'; give it in the case",
                           p->type_name[t]);
    }
    return 0;
}

int potential_find_file(const struct cfg *c, const char *name, char *path, size_t len)
{
    if (cfg_find_file(c, name, path, len) == 0)
        return 0;
    if (strchr(name, '/'))
        return -1;
    const char *env = getenv("CASCADE_POTENTIALS");
    const char *dirs[] = {env, "/usr/share/lammps/potentials"};
    for (size_t k = 0; k < sizeof dirs / sizeof *dirs; k++) {
        if (!dirs[k] || !*dirs[k])
            continue;
        snprintf(path, len, "%s/%s", dirs[k], name);
        if (access(path, R_OK) == 0)
            return 0;
    }
    snprintf(path, len, "%s", name);
    return -1;
}


int potential_file_key(struct cfg_obj *o, char *path, size_t len)
{
    const char *file;
    int rc = cfg_string(o, "file", NULL, &file);
    if (rc || o->cfg->shallow)
        return rc;
    if (potential_find_file(o->cfg, file, path, len) != 0) {
        char kp[CFG_PATH_MAX];
        snprintf(kp, sizeof kp, "%s.file", o->path);
        return cfg_error_at(o->cfg, kp,
                            "potential file '%s' not found (looked next to the case file, in the "
                            "current directory, $CASCADE_POTENTIALS and "
                            "/usr/share/lammps/potentials)",
                            file);
    }
    return 0;
}
