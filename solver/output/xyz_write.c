/* xyz_write: extended XYZ output (column names in xyz_write.h). */
#include "output/xyz_write.h"

#include <math.h>

#include "core/units.h"
#include "output/provenance.h"

void xyz_write_header(FILE *out, long n, const struct box *b, long step, double time, int pe,
                      int stress, const char *int_name)
{
    int extra = int_name != NULL;
    fprintf(out, "%ld\n", n);
    fprintf(out,
            "Lattice=\"%.10g 0 0 %.10g %.10g 0 %.10g %.10g %.10g\" Origin=\"%.10g %.10g %.10g\" "
            "Properties=species:S:1:pos:R:3:velo:R:3:forces:R:3:id:I:1:masses:R:1:momenta:R:3"
            "%s%s%s%s%s Time=%.10g Step=%ld pbc=\"%c %c %c\" "
            "units=\"pos:Å velo:Å/ps forces:eV/Å masses:amu momenta:amu*Å/(Å*sqrt(amu/eV))%s%s "
            "Time:ps\" program=\"cascade-solver %s (git %s)\"\n",
            box_length(b, 0), b->tilt[0], box_length(b, 1), b->tilt[1], b->tilt[2],
            box_length(b, 2), b->lo[0], b->lo[1], b->lo[2],
            pe ? ":energies:R:1" : "", stress ? ":stress:R:6" : "", extra ? ":" : "",
            extra ? int_name : "", extra ? ":I:1" : "", time, step,
            b->bc[0] == BOUNDARY_PERIODIC ? 'T' : 'F', b->bc[1] == BOUNDARY_PERIODIC ? 'T' : 'F',
            b->bc[2] == BOUNDARY_PERIODIC ? 'T' : 'F', pe ? " energies:eV" : "",
            stress ? " stress:GPa(xx,yy,zz,xy,xz,yz)" : "", provenance_version(),
            provenance_git_hash());
}

int xyz_write_particles(FILE *out, const struct particles *p, const struct xyz_extra *x)
{
    static const struct xyz_extra none;
    if (!x)
        x = &none;
    int extra = x->int_name && x->int_values;
    /* ASE's unit of time is Å sqrt(amu/eV): its momenta are amu Å/ps times
     * that time in ps, sqrt(amu Å^2/ps^2 in eV) */
    const double t_ase = sqrt(UNITS_MVV2E);
    for (int i = 0; i < p->n_owned; i++) {
        const double *r = p->x + 3 * i, *v = p->v + 3 * i, *f = p->f + 3 * i;
        double m = p->mass[p->type[i]];
        fprintf(out, "%s %.10g %.10g %.10g %.10g %.10g %.10g %.10g %.10g %.10g %lld %.10g "
                     "%.10g %.10g %.10g",
                p->type_name[p->type[i]], r[0], r[1], r[2], v[0], v[1], v[2], f[0], f[1], f[2],
                (long long)p->id[i], m, m * v[0] * t_ase, m * v[1] * t_ase, m * v[2] * t_ase);
        if (x->pe)
            fprintf(out, " %.10g", x->pe[i]);
        if (x->stress)
            for (int c = 0; c < 6; c++)
                fprintf(out, " %.10g", x->stress[6 * i + c]);
        if (extra)
            fprintf(out, " %d", x->int_values[i]);
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}

int xyz_write_frame(FILE *out, const struct particles *p, const struct box *b, long step,
                    double time, const struct xyz_extra *x)
{
    static const struct xyz_extra none;
    if (!x)
        x = &none;
    xyz_write_header(out, p->n_owned, b, step, time, x->pe != NULL, x->stress != NULL,
                     x->int_name && x->int_values ? x->int_name : NULL);
    return xyz_write_particles(out, p, x);
}
