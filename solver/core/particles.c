/* particles: allocation, growth, permutation of the structure of arrays. */
#include "core/particles.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/units.h"

struct particles *particles_create(int capacity)
{
    struct particles *p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    if (capacity < 16)
        capacity = 16;
    if (particles_reserve(p, capacity, NULL) != 0) {
        particles_destroy(&p);
        return NULL;
    }
    return p;
}

void particles_destroy(struct particles **pp)
{
    struct particles *p = pp ? *pp : NULL;
    if (!p)
        return;
    free(p->x); free(p->v); free(p->f); free(p->type); free(p->id); free(p->mask);
    free(p->image); free(p->origin); free(p->gshift); free(p->pe); free(p->virial);
    for (int i = 0; i < p->nfields; i++)
        free(p->fields[i].data);
    free(p);
    *pp = NULL;
}

#define GROW(ptr, count)                                                   \
    do {                                                                   \
        void *np_ = realloc((ptr), (size_t)(count) * sizeof *(ptr));       \
        if (!np_)                                                          \
            return err_nomem(e, "particle arrays");                        \
        (ptr) = np_;                                                       \
    } while (0)

int particles_reserve(struct particles *p, int n, struct err *e)
{
    if (n <= p->capacity)
        return 0;
    int cap = p->capacity ? p->capacity : 16;
    while (cap < n)
        cap = cap + cap / 2 + 16;
    GROW(p->x, 3 * cap);
    GROW(p->v, 3 * cap);
    GROW(p->f, 3 * cap);
    GROW(p->type, cap);
    GROW(p->id, cap);
    GROW(p->mask, cap);
    GROW(p->image, 3 * cap);
    GROW(p->origin, cap);
    GROW(p->gshift, 3 * cap);
    GROW(p->pe, cap);
    GROW(p->virial, 6 * cap);
    for (int i = 0; i < p->nfields; i++)
        GROW(p->fields[i].data, (size_t)p->fields[i].ncomp * cap);
    p->capacity = cap;
    return 0;
}

int particles_fit(struct particles *p, int n, struct err *e)
{
    if (n < p->n_owned + p->n_ghost)
        n = p->n_owned + p->n_ghost;
    if (n < 16)
        n = 16;
    if (n >= p->capacity)
        return 0;
    int cap = n;
    GROW(p->x, 3 * cap);
    GROW(p->v, 3 * cap);
    GROW(p->f, 3 * cap);
    GROW(p->type, cap);
    GROW(p->id, cap);
    GROW(p->mask, cap);
    GROW(p->image, 3 * cap);
    GROW(p->origin, cap);
    GROW(p->gshift, 3 * cap);
    GROW(p->pe, cap);
    GROW(p->virial, 6 * cap);
    for (int i = 0; i < p->nfields; i++)
        GROW(p->fields[i].data, (size_t)p->fields[i].ncomp * cap);
    p->capacity = cap;
    return 0;
}

int particles_add(struct particles *p, const double x[3], const double v[3], int type, int64_t id)
{
    int i = p->n_owned;
    if (particles_reserve(p, i + 1, NULL) != 0)
        return -1;
    for (int d = 0; d < 3; d++) {
        p->x[3 * i + d] = x[d];
        p->v[3 * i + d] = v ? v[d] : 0.0;
        p->f[3 * i + d] = 0.0;
        p->image[3 * i + d] = 0;
        p->gshift[3 * i + d] = 0;
    }
    p->type[i] = type;
    p->id[i] = id;
    p->mask[i] = 1u;   /* bit 0: group "all" */
    p->origin[i] = i;
    p->pe[i] = 0.0;
    memset(p->virial + 6 * i, 0, 6 * sizeof(double));
    for (int k = 0; k < p->nfields; k++)
        memset(p->fields[k].data + (size_t)p->fields[k].ncomp * i, 0,
               (size_t)p->fields[k].ncomp * sizeof(double));
    p->n_owned++;
    return i;
}

int particles_add_field(struct particles *p, const char *name, int ncomp, int ghost_copy,
                        struct err *e)
{
    int idx = particles_find_field(p, name);
    if (idx >= 0)
        return idx;
    if (p->nfields >= PARTICLES_MAX_FIELDS) {
        err_set(e, ERR_RUNTIME, "too many per-particle fields (adding '%s')", name);
        return -1;
    }
    struct particle_field *fl = &p->fields[p->nfields];
    memset(fl, 0, sizeof *fl);
    snprintf(fl->name, sizeof fl->name, "%s", name);
    fl->ncomp = ncomp;
    fl->ghost_copy = ghost_copy;
    fl->data = calloc((size_t)ncomp * (p->capacity ? p->capacity : 1), sizeof(double));
    if (!fl->data) {
        err_nomem(e, "particle field");
        return -1;
    }
    return p->nfields++;
}

int particles_find_field(const struct particles *p, const char *name)
{
    for (int i = 0; i < p->nfields; i++)
        if (strcmp(p->fields[i].name, name) == 0)
            return i;
    return -1;
}

void particles_remove_field(struct particles *p, const char *name)
{
    int idx = particles_find_field(p, name);
    if (idx < 0)
        return;
    free(p->fields[idx].data);
    memmove(p->fields + idx, p->fields + idx + 1,
            (size_t)(p->nfields - idx - 1) * sizeof p->fields[0]);
    p->nfields--;
    memset(&p->fields[p->nfields], 0, sizeof p->fields[0]);
}

void particles_copy_one(struct particles *p, int dst, int src)
{
    if (dst == src)
        return;
    memcpy(p->x + 3 * dst, p->x + 3 * src, 3 * sizeof(double));
    memcpy(p->v + 3 * dst, p->v + 3 * src, 3 * sizeof(double));
    memcpy(p->f + 3 * dst, p->f + 3 * src, 3 * sizeof(double));
    memcpy(p->image + 3 * dst, p->image + 3 * src, 3 * sizeof(int));
    memcpy(p->gshift + 3 * dst, p->gshift + 3 * src, 3 * sizeof(int));
    memcpy(p->virial + 6 * dst, p->virial + 6 * src, 6 * sizeof(double));
    p->type[dst] = p->type[src];
    p->id[dst] = p->id[src];
    p->mask[dst] = p->mask[src];
    p->origin[dst] = p->origin[src];
    p->pe[dst] = p->pe[src];
    for (int k = 0; k < p->nfields; k++) {
        int nc = p->fields[k].ncomp;
        memcpy(p->fields[k].data + (size_t)nc * dst, p->fields[k].data + (size_t)nc * src,
               (size_t)nc * sizeof(double));
    }
}

#define PERMUTE(arr, T, nc)                                                       \
    do {                                                                          \
        T *tmp_ = malloc((size_t)n * (nc) * sizeof(T));                           \
        if (!tmp_)                                                                \
            return err_nomem(e, "permutation buffer");                            \
        for (int k_ = 0; k_ < n; k_++)                                            \
            memcpy(tmp_ + (size_t)k_ * (nc), (arr) + (size_t)perm[k_] * (nc),     \
                   (nc) * sizeof(T));                                             \
        memcpy((arr), tmp_, (size_t)n * (nc) * sizeof(T));                        \
        free(tmp_);                                                               \
    } while (0)

int particles_permute(struct particles *p, const int *perm, struct err *e)
{
    int n = p->n_owned;
    PERMUTE(p->x, double, 3);
    PERMUTE(p->v, double, 3);
    PERMUTE(p->f, double, 3);
    PERMUTE(p->image, int, 3);
    PERMUTE(p->virial, double, 6);
    PERMUTE(p->type, int, 1);
    PERMUTE(p->id, int64_t, 1);
    PERMUTE(p->mask, uint32_t, 1);
    PERMUTE(p->pe, double, 1);
    for (int k = 0; k < p->nfields; k++)
        PERMUTE(p->fields[k].data, double, p->fields[k].ncomp);
    for (int i = 0; i < n; i++)
        p->origin[i] = i;
    return 0;
}

void particles_compact(struct particles *p, const unsigned char *keep)
{
    int w = 0;
    for (int i = 0; i < p->n_owned; i++) {
        if (!keep[i])
            continue;
        particles_copy_one(p, w, i);
        p->origin[w] = w;
        w++;
    }
    p->n_owned = w;
}

int particles_type_index(struct particles *p, const char *name, double mass)
{
    for (int t = 0; t < p->ntypes; t++)
        if (strcmp(p->type_name[t], name) == 0)
            return t;
    if (p->ntypes >= PARTICLES_MAX_TYPES)
        return -1;
    int t = p->ntypes++;
    snprintf(p->type_name[t], sizeof p->type_name[t], "%s", name);
    p->mass[t] = mass;
    return t;
}

void particles_kinetic_tensor(const struct particles *p, double k[6])
{
    for (int c = 0; c < 6; c++)
        k[c] = 0;
    for (int i = 0; i < p->n_owned; i++) {
        double m = p->mass[p->type[i]] * UNITS_MVV2E;
        const double *v = p->v + 3 * i;
        k[0] += m * v[0] * v[0];
        k[1] += m * v[1] * v[1];
        k[2] += m * v[2] * v[2];
        k[3] += m * v[0] * v[1];
        k[4] += m * v[0] * v[2];
        k[5] += m * v[1] * v[2];
    }
}
