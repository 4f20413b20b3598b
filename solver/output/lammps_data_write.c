/* lammps_data_write: atom_style atomic data files. */
#include "output/lammps_data_write.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "util/wfile.h"

void lammps_data_widen(const struct particles *p, const struct box *b, double lo[3], double hi[3])
{
    for (int d = 0; d < 3; d++) {
        if (b->bc[d] == BOUNDARY_PERIODIC)
            continue;
        for (int i = 0; i < p->n_owned; i++) {
            double x = p->x[3 * i + d];
            lo[d] = fmin(lo[d], x);
            hi[d] = fmax(hi[d], x);
        }
    }
}

void lammps_data_header(FILE *f, const char *title, long natoms, const struct particles *types,
                        const double lo[3], const double hi[3], const struct box *b)
{
    fprintf(f, "%s\n\n", title && title[0] ? title : "written by cascade-solver");
    fprintf(f, "%ld atoms\n%d atom types\n\n", natoms, types->ntypes);
    for (int d = 0; d < 3; d++)   /* a flat free axis gets a unit width */
        fprintf(f, "%.17g %.17g %clo %chi\n", lo[d], hi[d] > lo[d] ? hi[d] : lo[d] + 1.0,
                "xyz"[d], "xyz"[d]);
    if (box_tilted(b))   /* LAMMPS' restricted triclinic cell (core/box.h) */
        fprintf(f, "%.17g %.17g %.17g xy xz yz\n", b->tilt[0], b->tilt[1], b->tilt[2]);
    fprintf(f, "\nMasses\n\n");
    for (int t = 0; t < types->ntypes; t++)
        fprintf(f, "%d %.17g # %s\n", t + 1, types->mass[t], types->type_name[t]);
    fprintf(f, "\nAtoms # atomic\n\n");
}

void lammps_data_atoms(FILE *f, const struct particles *p)
{
    for (int i = 0; i < p->n_owned; i++) {
        const double *x = p->x + 3 * i;
        const int *im = p->image + 3 * i;
        fprintf(f, "%lld %d %.17g %.17g %.17g %d %d %d\n", (long long)p->id[i], p->type[i] + 1,
                x[0], x[1], x[2], im[0], im[1], im[2]);
    }
}

void lammps_data_velocities_heading(FILE *f)
{
    fprintf(f, "\nVelocities\n\n");
}

void lammps_data_velocities(FILE *f, const struct particles *p)
{
    for (int i = 0; i < p->n_owned; i++) {
        const double *v = p->v + 3 * i;
        fprintf(f, "%lld %.17g %.17g %.17g\n", (long long)p->id[i], v[0], v[1], v[2]);
    }
}

int lammps_data_write(const char *path, const struct particles *p, const struct box *b,
                      const char *title, struct err *e)
{
    double lo[3] = {b->lo[0], b->lo[1], b->lo[2]}, hi[3] = {b->hi[0], b->hi[1], b->hi[2]};
    lammps_data_widen(p, b, lo, hi);
    struct wfile w;
    int rc = wfile_open(&w, path, e);
    if (rc)
        return rc;
    lammps_data_header(w.f, title, p->n_owned, p, lo, hi, b);
    lammps_data_atoms(w.f, p);
    lammps_data_velocities_heading(w.f);
    lammps_data_velocities(w.f, p);
    return wfile_commit(&w, e);
}
