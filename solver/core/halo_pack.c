/* halo_pack: particles as byte records (halo_pack.h). */
#include "core/halo_pack.h"

#include <stdint.h>
#include <string.h>

size_t halo_record_size(const struct particles *p)
{
    size_t n = (3 + 3 + 3 + 1 + 6) * sizeof(double) + sizeof(int) + sizeof(int64_t) +
               sizeof(uint32_t) + 3 * sizeof(int) + 3 * sizeof(int);
    for (int k = 0; k < p->nfields; k++)
        n += (size_t)p->fields[k].ncomp * sizeof(double);
    return n;
}

#define PUT(src, bytes)                  \
    do {                                 \
        memcpy(buf, (src), (bytes));     \
        buf += (bytes);                  \
    } while (0)
#define GET(dst, bytes)                  \
    do {                                 \
        memcpy((dst), buf, (bytes));     \
        buf += (bytes);                  \
    } while (0)

/* The box shift of the copy of particle i sent across dim: an owned
 * particle is its own copy (its slot may hold a stale ghost's count: a
 * checkpoint read refills slots), a ghost adds this hop to its own. */
static void copy_shift(const struct particles *p, int i, int dim, double shift, int gs[3])
{
    gs[0] = gs[1] = gs[2] = 0;
    if (i >= p->n_owned)
        memcpy(gs, p->gshift + 3 * (size_t)i, 3 * sizeof(int));
    if (dim >= 0 && shift != 0)
        gs[dim] += shift > 0 ? 1 : -1;
}

void halo_pack(const struct particles *p, int i, int dim, double shift, unsigned char *buf)
{
    double x[3] = {p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2]};
    if (dim >= 0)
        x[dim] += shift;
    PUT(x, sizeof x);
    PUT(p->v + 3 * (size_t)i, 3 * sizeof(double));
    PUT(p->f + 3 * (size_t)i, 3 * sizeof(double));
    PUT(p->pe + i, sizeof(double));
    PUT(p->virial + 6 * (size_t)i, 6 * sizeof(double));
    PUT(p->type + i, sizeof(int));
    PUT(p->id + i, sizeof(int64_t));
    PUT(p->mask + i, sizeof(uint32_t));
    PUT(p->image + 3 * (size_t)i, 3 * sizeof(int));
    /* box lengths the copy is shifted by from its owner: the DPD pair keys
     * (dpd/dpd_pair.h) tell periodic images of one pair apart with it */
    int gs[3];
    copy_shift(p, i, dim, shift, gs);
    PUT(gs, sizeof gs);
    for (int k = 0; k < p->nfields; k++) {
        size_t nc = (size_t)p->fields[k].ncomp;
        PUT(p->fields[k].data + nc * i, nc * sizeof(double));
    }
}

void halo_unpack(struct particles *p, int i, const unsigned char *buf)
{
    GET(p->x + 3 * (size_t)i, 3 * sizeof(double));
    GET(p->v + 3 * (size_t)i, 3 * sizeof(double));
    GET(p->f + 3 * (size_t)i, 3 * sizeof(double));
    GET(p->pe + i, sizeof(double));
    GET(p->virial + 6 * (size_t)i, 6 * sizeof(double));
    GET(p->type + i, sizeof(int));
    GET(p->id + i, sizeof(int64_t));
    GET(p->mask + i, sizeof(uint32_t));
    GET(p->image + 3 * (size_t)i, 3 * sizeof(int));
    GET(p->gshift + 3 * (size_t)i, 3 * sizeof(int));
    for (int k = 0; k < p->nfields; k++) {
        size_t nc = (size_t)p->fields[k].ncomp;
        GET(p->fields[k].data + nc * i, nc * sizeof(double));
    }
    p->origin[i] = i;
}

size_t halo_ghost_record_size(const struct particles *p)
{
    size_t n = (3 + 3) * sizeof(double) + sizeof(int) + sizeof(int64_t) + sizeof(uint32_t) +
               3 * sizeof(int) + 3 * sizeof(int);
    for (int k = 0; k < p->nfields; k++)
        n += (size_t)p->fields[k].ncomp * sizeof(double);
    return n;
}

void halo_pack_ghost(const struct particles *p, int i, int dim, double shift, const double *vec,
                     unsigned char *buf)
{
    double x[3] = {p->x[3 * i], p->x[3 * i + 1], p->x[3 * i + 2]};
    if (vec)
        for (int c = 0; c < 3; c++)
            x[c] += vec[c];
    else if (dim >= 0)
        x[dim] += shift;
    PUT(x, sizeof x);
    PUT(p->v + 3 * (size_t)i, 3 * sizeof(double));
    PUT(p->type + i, sizeof(int));
    PUT(p->id + i, sizeof(int64_t));
    PUT(p->mask + i, sizeof(uint32_t));
    /* the owner's image counts and the box shift, as in halo_pack: DPD's
     * pair keys (dpd/dpd_pair.h) need both on ghosts */
    PUT(p->image + 3 * (size_t)i, 3 * sizeof(int));
    int gs[3];
    copy_shift(p, i, dim, shift, gs);
    PUT(gs, sizeof gs);
    for (int k = 0; k < p->nfields; k++) {
        size_t nc = (size_t)p->fields[k].ncomp;
        PUT(p->fields[k].data + nc * i, nc * sizeof(double));
    }
}

void halo_unpack_ghost(struct particles *p, int i, const unsigned char *buf)
{
    GET(p->x + 3 * (size_t)i, 3 * sizeof(double));
    GET(p->v + 3 * (size_t)i, 3 * sizeof(double));
    GET(p->type + i, sizeof(int));
    GET(p->id + i, sizeof(int64_t));
    GET(p->mask + i, sizeof(uint32_t));
    GET(p->image + 3 * (size_t)i, 3 * sizeof(int));
    GET(p->gshift + 3 * (size_t)i, 3 * sizeof(int));
    for (int k = 0; k < p->nfields; k++) {
        size_t nc = (size_t)p->fields[k].ncomp;
        GET(p->fields[k].data + nc * i, nc * sizeof(double));
    }
    /* a ghost's force, energy and virial are partial sums the kernels zero
     * and the reverse communication takes back to the owner */
    memset(p->f + 3 * (size_t)i, 0, 3 * sizeof(double));
    p->pe[i] = 0.0;
    memset(p->virial + 6 * (size_t)i, 0, 6 * sizeof(double));
    p->origin[i] = i;
}
