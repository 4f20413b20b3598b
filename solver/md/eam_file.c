/* eam_file: funcfl / setfl / fs readers (see eam_file.h). */
#include "md/eam_file.h"

#include <stdlib.h>
#include <string.h>

#include "core/textfile.h"

static const char *element_of_z(long z)
{
    static const char *const sym[] = {
        "", "H", "He", "Li", "Be", "B", "C", "N", "O", "F", "Ne", "Na", "Mg", "Al", "Si", "P", "S",
        "Cl", "Ar", "K", "Ca", "Sc", "Ti", "V", "Cr", "Mn", "Fe", "Co", "Ni", "Cu", "Zn", "Ga",
        "Ge", "As", "Se", "Br", "Kr", "Rb", "Sr", "Y", "Zr", "Nb", "Mo", "Tc", "Ru", "Rh", "Pd",
        "Ag", "Cd", "In", "Sn", "Sb", "Te", "I", "Xe", "Cs", "Ba", "La", "Ce", "Pr", "Nd", "Pm",
        "Sm", "Eu", "Gd", "Tb", "Dy", "Ho", "Er", "Tm", "Yb", "Lu", "Hf", "Ta", "W", "Re", "Os",
        "Ir", "Pt", "Au", "Hg", "Tl", "Pb"};
    if (z > 0 && z < (long)(sizeof sym / sizeof *sym))
        return sym[z];
    return "X";
}

static double *alloc_table(long n, struct err *e)
{
    double *t = malloc((size_t)(n > 0 ? n : 1) * sizeof *t);
    if (!t)
        err_nomem(e, "EAM table");
    return t;
}

/* `min` points per table: 5 for the splines (eam_spline_build), one more
 * for funcfl, whose last point is dropped. */
static int check_grid(struct textfile *t, long nrho, double drho, long nr, double dr, double cut,
                      long min, struct err *e)
{
    if (nrho < min || nr < min)
        return textfile_error(t, e, "tables need at least %ld points (Nrho = %ld, Nr = %ld)", min,
                              nrho, nr);
    if (nrho > 10000000 || nr > 10000000)
        return textfile_error(t, e, "implausibly large tables (Nrho = %ld, Nr = %ld)", nrho, nr);
    if (!(drho > 0) || !(dr > 0) || !(cut > 0))
        return textfile_error(t, e, "drho = %g, dr = %g and cutoff = %g must be positive", drho,
                              dr, cut);
    return 0;
}

static int read_funcfl(struct textfile *t, struct eam_data *d, struct err *e)
{
    long z, nrho, nr;
    double mass, alat, drho, dr, cut;
    int rc;
    if (textfile_next_line(t) != 0)   /* comment line */
        return textfile_error(t, e, "empty file");
    t->cursor = t->buf + strlen(t->buf);
    if ((rc = textfile_int(t, &z, "the atomic number", e)) ||
        (rc = textfile_double(t, &mass, "the mass", e)) ||
        (rc = textfile_double(t, &alat, "the lattice constant", e)))
        return rc;
    t->cursor = t->buf + strlen(t->buf);   /* skip the lattice name */
    if ((rc = textfile_int(t, &nrho, "Nrho", e)) || (rc = textfile_double(t, &drho, "drho", e)) ||
        (rc = textfile_int(t, &nr, "Nr", e)) || (rc = textfile_double(t, &dr, "dr", e)) ||
        (rc = textfile_double(t, &cut, "the cutoff", e)))
        return rc;
    d->cut_line = t->line;
    if ((rc = check_grid(t, nrho, drho, nr, dr, cut, 6, e)))
        return rc;
    if (!(mass > 0))
        return textfile_error(t, e, "mass must be positive, found %g", mass);
    double *F = alloc_table(nrho, e), *Z = alloc_table(nr, e), *R = alloc_table(nr, e);
    if (!F || !Z || !R) {
        free(F); free(Z); free(R);
        return ERR_RUNTIME;
    }
    rc = textfile_doubles(t, F, nrho, "F(rho)", e);
    if (!rc) rc = textfile_doubles(t, Z, nr, "Z(r)", e);
    if (!rc) rc = textfile_doubles(t, R, nr, "rho(r)", e);
    if (rc) {
        free(F); free(Z); free(R);
        return rc;
    }
    d->ne = 1;
    snprintf(d->element[0], sizeof d->element[0], "%s", element_of_z(z));
    d->mass[0] = mass;
    /* LAMMPS's grid for one funcfl file: the same spacing, one knot fewer */
    d->nrho = (int)nrho - 1;
    d->nr = (int)nr - 1;
    d->drho = drho;
    d->dr = dr;
    d->cut = cut;
    d->rhomax = (double)(nrho - 1) * drho;
    d->frho[0] = F;
    d->rhor[0] = R;
    d->z2r[0] = Z;
    for (int m = 0; m < d->nr; m++)
        Z[m] = 27.2 * 0.529 * Z[m] * Z[m];
    return 0;
}

static int read_setfl_like(struct textfile *t, struct eam_data *d, int fs, struct err *e)
{
    int rc;
    for (int k = 0; k < 3; k++)
        if (textfile_next_line(t) != 0)
            return textfile_error(t, e, "unexpected end of file in the 3 comment lines");
    t->cursor = t->buf + strlen(t->buf);
    long ne;
    if ((rc = textfile_int(t, &ne, "the number of elements", e)))
        return rc;
    if (ne < 1 || ne > PARTICLES_MAX_TYPES)
        return textfile_error(t, e, "number of elements must be 1..%d, found %ld",
                              PARTICLES_MAX_TYPES, ne);
    for (long k = 0; k < ne; k++) {
        const char *tok = textfile_token(t);
        if (!tok)
            return textfile_error(t, e, "missing element name %ld", k + 1);
        if (strlen(tok) >= sizeof d->element[k]) {
            /* cut to fit, it would name another element (or none) */
            char ex[TEXT_EXCERPT_SIZE];
            return textfile_error(t, e, "element name %ld '%s' is longer than %zu characters",
                                  k + 1, text_excerpt(tok, ex), sizeof d->element[k] - 1);
        }
        snprintf(d->element[k], sizeof d->element[k], "%s", tok);
    }
    long nrho, nr;
    double drho, dr, cut;
    if ((rc = textfile_int(t, &nrho, "Nrho", e)) || (rc = textfile_double(t, &drho, "drho", e)) ||
        (rc = textfile_int(t, &nr, "Nr", e)) || (rc = textfile_double(t, &dr, "dr", e)) ||
        (rc = textfile_double(t, &cut, "the cutoff", e)))
        return rc;
    d->cut_line = t->line;
    if ((rc = check_grid(t, nrho, drho, nr, dr, cut, 5, e)))
        return rc;
    d->ne = (int)ne;
    d->nrho = (int)nrho;
    d->nr = (int)nr;
    d->drho = drho;
    d->dr = dr;
    d->cut = cut;
    d->rhomax = (double)(nrho - 1) * drho;
    for (long a = 0; a < ne; a++) {
        long z;
        double alat;
        if ((rc = textfile_int(t, &z, "the atomic number", e)) ||
            (rc = textfile_double(t, &d->mass[a], "the mass", e)) ||
            (rc = textfile_double(t, &alat, "the lattice constant", e)))
            return rc;
        if (!(d->mass[a] > 0))
            return textfile_error(t, e, "mass of %s must be positive, found %g", d->element[a],
                                  d->mass[a]);
        t->cursor = t->buf + strlen(t->buf);   /* lattice name */
        if (!(d->frho[a] = alloc_table(nrho, e)))
            return ERR_RUNTIME;
        char what[64];
        snprintf(what, sizeof what, "F(rho) of %s", d->element[a]);
        if ((rc = textfile_doubles(t, d->frho[a], nrho, what, e)))
            return rc;
        /* setfl: one density function per element (same for every host);
         * fs: one per (this element, host element) pair */
        int nfun = fs ? (int)ne : 1;
        for (int b = 0; b < nfun; b++) {
            double *r = alloc_table(nr, e);
            if (!r)
                return ERR_RUNTIME;
            snprintf(what, sizeof what, "rho(r) of %s", d->element[a]);
            if ((rc = textfile_doubles(t, r, nr, what, e))) {
                free(r);
                return rc;
            }
            /* setfl keeps its one function in slot (a, 0) */
            d->rhor[a * ne + b] = r;
        }
    }
    for (long a = 0; a < ne; a++)
        for (long b = 0; b <= a; b++) {
            double *z2 = alloc_table(nr, e);
            if (!z2)
                return ERR_RUNTIME;
            char what[64];
            snprintf(what, sizeof what, "r*phi(r) of %s-%s", d->element[a], d->element[b]);
            if ((rc = textfile_doubles(t, z2, nr, what, e))) {
                free(z2);
                return rc;
            }
            d->z2r[a * ne + b] = z2;   /* symmetric: stored once, a >= b */
        }
    return 0;
}

int eam_data_read(const char *path, enum eam_format fmt, struct eam_data *d, struct err *e)
{
    memset(d, 0, sizeof *d);
    d->format = fmt;
    struct textfile t;
    int rc = textfile_open(&t, path, e);
    if (rc)
        return rc;
    rc = fmt == EAM_FUNCFL ? read_funcfl(&t, d, e) : read_setfl_like(&t, d, fmt == EAM_FS, e);
    textfile_close(&t);
    if (rc)
        eam_data_free(d);
    return rc;
}

void eam_data_free(struct eam_data *d)
{
    for (int a = 0; a < PARTICLES_MAX_TYPES; a++)
        free(d->frho[a]);
    for (int k = 0; k < PARTICLES_MAX_TYPES * PARTICLES_MAX_TYPES; k++) {
        free(d->rhor[k]);
        free(d->z2r[k]);
    }
    memset(d, 0, sizeof *d);
}
