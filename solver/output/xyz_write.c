/* xyz_write: extended XYZ output. */
#include "output/xyz_write.h"

#include "output/provenance.h"

int xyz_write_frame(FILE *out, const struct particles *p, const struct box *b, long step,
                    double time, const char *extra_name, const int *extra)
{
    fprintf(out, "%d\n", p->n_owned);
    fprintf(out,
            "Lattice=\"%.10g 0 0 0 %.10g 0 0 0 %.10g\" Origin=\"%.10g %.10g %.10g\" "
            "Properties=species:S:1:pos:R:3:vel:R:3:forces:R:3:id:I:1%s%s%s Time=%.10g Step=%ld "
            "pbc=\"%c %c %c\" units=\"pos:Å vel:Å/ps forces:eV/Å Time:ps\" "
            "program=\"cascade-solver %s (git %s)\"\n",
            box_length(b, 0), box_length(b, 1), box_length(b, 2), b->lo[0], b->lo[1], b->lo[2],
            extra ? ":" : "", extra ? extra_name : "", extra ? ":I:1" : "", time, step,
            b->bc[0] == BOUNDARY_PERIODIC ? 'T' : 'F', b->bc[1] == BOUNDARY_PERIODIC ? 'T' : 'F',
            b->bc[2] == BOUNDARY_PERIODIC ? 'T' : 'F', provenance_version(), provenance_git_hash());
    for (int i = 0; i < p->n_owned; i++) {
        const double *x = p->x + 3 * i, *v = p->v + 3 * i, *f = p->f + 3 * i;
        fprintf(out, "%s %.10g %.10g %.10g %.8g %.8g %.8g %.8g %.8g %.8g %lld", p->type_name[p->type[i]],
                x[0], x[1], x[2], v[0], v[1], v[2], f[0], f[1], f[2], (long long)p->id[i]);
        if (extra)
            fprintf(out, " %d", extra[i]);
        fputc('\n', out);
    }
    return ferror(out) ? -1 : 0;
}
