/* sputter: union-find over neighbour pairs, then the groups that left. */
#include "analysis/sputter.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int find_root(int *parent, int i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];   /* path halving */
        i = parent[i];
    }
    return i;
}

struct link {
    const struct frame *f;
    int *parent;
    int i;
};

static void link_cb(void *ctx, int entry, double r2)
{
    (void)r2;
    struct link *l = ctx;
    int a = find_root(l->parent, l->i), b = find_root(l->parent, l->f->origin[entry]);
    if (a != b) {
        if (a < b)
            l->parent[b] = a;   /* smallest index as root: reproducible */
        else
            l->parent[a] = b;
    }
}

int sputter_find(const struct frame *f, const double *v, const double *mass,
                 const struct sputter_params *p, unsigned char *state,
                 struct sputter_stats *out, struct err *e)
{
    int n = f->n;
    memset(out, 0, sizeof *out);
    if (p->cutoff > f->range * (1 + 1e-12))
        return err_set(e, ERR_RUNTIME, "sputter: connection cutoff %g Å exceeds the range %g Å "
                                       "of the frame", p->cutoff, f->range);
    int *parent = malloc((size_t)(n + 1) * sizeof *parent);
    long *size = calloc((size_t)(n + 1), sizeof *size);
    double *zmin = malloc((size_t)(n + 1) * sizeof *zmin);
    double *mv = calloc((size_t)(n + 1), sizeof *mv), *msum = calloc((size_t)(n + 1), sizeof *msum);
    if (!parent || !size || !zmin || !mv || !msum) {
        free(parent); free(size); free(zmin); free(mv); free(msum);
        return err_nomem(e, "sputter groups");
    }
    for (int i = 0; i < n; i++)
        parent[i] = i;
    struct link ctx = {f, parent, 0};
    for (int i = 0; i < n; i++) {
        ctx.i = i;
        frame_query(f, i, p->cutoff, link_cb, &ctx);
    }
    for (int i = 0; i < n; i++)
        zmin[i] = INFINITY;
    for (int i = 0; i < n; i++) {
        int r = find_root(parent, i);
        double m = mass ? mass[i] : 1.0, z = f->x[3 * i + p->axis];
        size[r]++;
        msum[r] += m;
        mv[r] += m * v[3 * i + p->axis];
        if (z < zmin[r])
            zmin[r] = z;
    }
    int target = -1;
    for (int i = 0; i < n; i++)
        if (parent[i] == i) {
            out->groups++;
            if (target < 0 || size[i] > size[target])
                target = i;
        }
    out->target = target >= 0 ? size[target] : 0;
    for (int i = 0; i < n; i++) {
        if (parent[i] != i || i == target)
            continue;
        if (zmin[i] > p->surface + p->margin && mv[i] / msum[i] > 0) {
            out->clusters++;
            out->atoms += size[i];
            if (size[i] == 1)
                out->monomers++;
            if (size[i] > out->largest)
                out->largest = size[i];
        } else {
            size[i] = -size[i];   /* mark: not sputtered */
        }
    }
    if (state)
        for (int i = 0; i < n; i++) {
            int r = find_root(parent, i);
            state[i] = r == target ? SPUTTER_TARGET : size[r] > 0 ? SPUTTER_LEFT : SPUTTER_DETACHED;
        }
    free(parent); free(size); free(zmin); free(mv); free(msum);
    return 0;
}
