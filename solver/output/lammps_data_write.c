/* lammps_data_write: atom_style atomic data files. */
#include "output/lammps_data_write.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "util/wfile.h"

int lammps_data_write(const char *path, const struct particles *p, const struct box *b,
                      const char *title, struct err *e)
{
    double lo[3], hi[3];
    for (int d = 0; d < 3; d++) {
        lo[d] = b->lo[d];
        hi[d] = b->hi[d];
        if (b->bc[d] == BOUNDARY_PERIODIC)
            continue;
        for (int i = 0; i < p->n_owned; i++) {
            double x = p->x[3 * i + d];
            lo[d] = fmin(lo[d], x);
            hi[d] = fmax(hi[d], x);
        }
        if (!(hi[d] > lo[d]))
            hi[d] = lo[d] + 1.0;
    }
    struct wfile w;
    int rc = wfile_open(&w, path, e);
    if (rc)
        return rc;
    FILE *f = w.f;
    fprintf(f, "%s\n\n", title && title[0] ? title : "written by cascade-solver");
    fprintf(f, "%d atoms\n%d atom types\n\n", p->n_owned, p->ntypes);
    for (int d = 0; d < 3; d++)
        fprintf(f, "%.17g %.17g %clo %chi\n", lo[d], hi[d], "xyz"[d], "xyz"[d]);
    if (box_tilted(b))   /* LAMMPS' restricted triclinic cell (core/box.h) */
        fprintf(f, "%.17g %.17g %.17g xy xz yz\n", b->tilt[0], b->tilt[1], b->tilt[2]);
    fprintf(f, "\nMasses\n\n");
    for (int t = 0; t < p->ntypes; t++)
        fprintf(f, "%d %.17g # %s\n", t + 1, p->mass[t], p->type_name[t]);
    fprintf(f, "\nAtoms # atomic\n\n");
    for (int i = 0; i < p->n_owned; i++) {
        const double *x = p->x + 3 * i;
        const int *im = p->image + 3 * i;
        fprintf(f, "%lld %d %.17g %.17g %.17g %d %d %d\n", (long long)p->id[i], p->type[i] + 1,
                x[0], x[1], x[2], im[0], im[1], im[2]);
    }
    fprintf(f, "\nVelocities\n\n");
    for (int i = 0; i < p->n_owned; i++) {
        const double *v = p->v + 3 * i;
        fprintf(f, "%lld %.17g %.17g %.17g\n", (long long)p->id[i], v[0], v[1], v[2]);
    }
    return wfile_commit(&w, e);
}
