/*
 * mpm_material: constitutive laws for material points, selected by name
 * from the case file (`law:`), as a table of function pointers -- adding a
 * law means one file and one line in mpm_material_registry.c.
 *
 * A law updates the Cauchy stress of one point from its strain increment
 * (Chen 2014, Eq. (s13)-(s14)); the driver (mpm_stress.c) first rotates the
 * stress with the Jaumann rate when the material asks for it, so laws are
 * written in the rotation-free frame.  Laws must be thread-safe: they read
 * the material and write only the point's stress and state.
 *
 * Every material has these keys (read by mpm_material_create):
 *   name:     label the bodies refer to
 *   law:      linear_elastic | cubic_elastic | j2
 *   density:  > 0 (g/cm^3 in metal units, kg/m^3 in SI)
 *   rate:     jaumann | none     objective stress rate (default jaumann)
 * and the law's own keys (moduli in GPa, or Pa in SI).
 */
#ifndef CASCADE_MPM_MATERIAL_H
#define CASCADE_MPM_MATERIAL_H

#include "mpm/mpm_units.h"
#include "util/cfg.h"
#include "util/err.h"

#define MPM_MAX_STATE 4

struct mpm_material;

/* Isotropic moduli (Lamé), for laws and the kernels' inlined update. */
struct mpm_iso {
    double lambda, mu;   /* eV/Å^3 */
};

struct mpm_material_ops {
    const char *law;
    int nstate;   /* state variables per point */
    /* sigma (6, eV/Å^3) += law increment for strain increment de (6,
     * tensor components); state: the point's nstate variables. */
    void (*update)(const struct mpm_material *m, double sigma[6], const double de[6],
                   double *state);
    /* Largest elastic wave speed (Å/ps), for the CFL time step. */
    double (*wave_speed)(const struct mpm_material *m);
    /* Names and units of the state variables (for output), may be NULL. */
    const char *const *state_names;
};

/* Base struct: the first member of every concrete material. */
struct mpm_material {
    const struct mpm_material_ops *ops;
    char name[32];
    double density;   /* amu/Å^3 */
    int jaumann;      /* rotate the stress with the Jaumann rate */
    const struct mpm_iso *iso;   /* linear_elastic: its moduli, so the point kernels
                                    inline the increment instead of calling ops->update
                                    (NULL for other laws) */
    char description[160];
};

/* Read one material object (common keys + the law's keys, converted from
 * `u`) and create it; in shallow mode *out stays NULL.  Errors name the key. */
int mpm_material_create(struct cfg_obj *o, const struct mpm_units *u, struct mpm_material **out);
void mpm_material_destroy(struct mpm_material **m);

/* Programmatic constructors, for tests and couplings (metal units: density
 * amu/Å^3, moduli and stresses eV/Å^3); NULL when out of memory.  The
 * Jaumann rate is on; set m->jaumann = 0 to switch it off. */
struct mpm_material *mpm_material_linear_elastic(const char *name, double density, double E,
                                                 double nu);
struct mpm_material *mpm_material_cubic_elastic(const char *name, double density, double c11,
                                                double c12, double c44);
/* A cubic crystal turned so that box axis i is the crystal direction R[i]
 * (rows: orthonormal unit vectors in crystal coordinates); the stiffness is
 * C'_ijkl = R_ia R_jb R_kc R_ld C_abcd. */
struct mpm_material *mpm_material_cubic_elastic_rotated(const char *name, double density,
                                                        double c11, double c12, double c44,
                                                        const double R[3][3]);
/* The Voigt stiffness (xx yy zz xy xz yz, on engineering shears) of a
 * cubic_elastic material in the box frame, eV/Å^3. */
void mpm_material_cubic_stiffness(const struct mpm_material *m, double C[6][6]);
struct mpm_material *mpm_material_j2(const char *name, double density, double E, double nu,
                                     double yield, double hardening);

/* The registry. */
struct mpm_material_style {
    const char *law;
    const char *summary;
    /* Read the law's keys from o (converted from u) and allocate; the
     * caller fills the base struct's common fields. */
    int (*create)(struct cfg_obj *o, const struct mpm_units *u, double density,
                  struct mpm_material **out);
};
extern const struct mpm_material_style mpm_material_styles[];   /* NULL-law terminated */

/* An error about key `key` of object o: "file:line:col: path.key: message". */
int mpm_key_error(struct cfg_obj *o, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* Fill the common fields (laws' programmatic constructors). */
void mpm_material_base_init(struct mpm_material *m, const char *name, double density);

/* Helpers for laws: isotropic moduli and the elastic increment. */
int mpm_iso_read(struct cfg_obj *o, const struct mpm_units *u, struct mpm_iso *iso, double *E,
                 double *nu);
static inline void mpm_iso_increment(const struct mpm_iso *c, double s[6], const double de[6])
{
    double tr = de[0] + de[1] + de[2];
    s[0] += c->lambda * tr + 2 * c->mu * de[0];
    s[1] += c->lambda * tr + 2 * c->mu * de[1];
    s[2] += c->lambda * tr + 2 * c->mu * de[2];
    s[3] += 2 * c->mu * de[3];
    s[4] += 2 * c->mu * de[4];
    s[5] += 2 * c->mu * de[5];
}

#endif
