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

int sputter_link(const struct frame *f, double cutoff, int *root, struct err *e)
{
    if (cutoff > f->range * (1 + 1e-12))
        return err_set(e, ERR_RUNTIME, "sputter: connection cutoff %g Å exceeds the range %g Å "
                                       "of the frame", cutoff, f->range);
    for (int i = 0; i < f->n; i++)
        root[i] = i;
    struct link ctx = {f, root, 0};
    for (int i = 0; i < f->n; i++) {
        ctx.i = i;
        frame_query(f, i, cutoff, link_cb, &ctx);
    }
    for (int i = 0; i < f->n; i++)
        root[i] = find_root(root, i);
    return 0;
}

long sputter_judge(struct sputter_group *g, long ng, const struct sputter_params *p,
                   struct sputter_stats *out)
{
    memset(out, 0, sizeof *out);
    long target = -1;
    for (long k = 0; k < ng; k++) {
        out->groups++;
        g[k].left = 0;
        if (target < 0 || g[k].size > g[target].size)
            target = k;
    }
    out->target = target >= 0 ? g[target].size : 0;
    for (long k = 0; k < ng; k++) {
        if (k == target)
            continue;
        if (g[k].zmin > p->surface + p->margin && g[k].momentum / g[k].mass > 0) {
            g[k].left = 1;
            out->clusters++;
            out->atoms += g[k].size;
            if (g[k].size == 1)
                out->monomers++;
            if (g[k].size > out->largest)
                out->largest = g[k].size;
        }
    }
    return target;
}

int sputter_find(const struct frame *f, const double *v, const double *mass,
                 const struct sputter_params *p, unsigned char *state,
                 struct sputter_stats *out, struct err *e)
{
    int n = f->n;
    memset(out, 0, sizeof *out);
    int *root = malloc((size_t)(n + 1) * sizeof *root);
    int *slot = malloc((size_t)(n + 1) * sizeof *slot);
    struct sputter_group *g = malloc((size_t)(n + 1) * sizeof *g);
    int rc = root && slot && g ? sputter_link(f, p->cutoff, root, e)
                               : err_nomem(e, "sputter groups");
    long ng = 0;
    /* the groups in the order of their roots (smallest index) */
    for (int i = 0; !rc && i < n; i++)
        if (root[i] == i) {
            slot[i] = (int)ng;
            g[ng++] = (struct sputter_group){i, 0, 0.0, 0.0, INFINITY, 0};
        }
    for (int i = 0; !rc && i < n; i++) {
        struct sputter_group *gi = &g[slot[root[i]]];
        double m = mass ? mass[i] : 1.0, z = f->x[3 * i + p->axis];
        gi->size++;
        gi->mass += m;
        gi->momentum += m * v[3 * i + p->axis];
        if (z < gi->zmin)
            gi->zmin = z;
    }
    if (!rc) {
        long target = sputter_judge(g, ng, p, out);
        for (int i = 0; state && i < n; i++) {
            long k = slot[root[i]];
            state[i] = k == target ? SPUTTER_TARGET : g[k].left ? SPUTTER_LEFT : SPUTTER_DETACHED;
        }
    }
    free(root); free(slot); free(g);
    return rc;
}
