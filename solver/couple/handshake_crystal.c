/* handshake_crystal: the crystal the MPM side must match -- lattice
 * constant, cohesive energy and C11, C12, C44 from the same potential as
 * the MD (Guo & Yang 2005, section 2.2: "these constants can be derived
 * from the atomic potential and then are used in the MPM region"). */
#include <stdio.h>
#include <string.h>

#include "core/elements.h"
#include "couple/handshake.h"
#include "md/crystal.h"

int handshake_crystal_from_potential(struct potential *pot, const char *element, double a_min,
                                     double a_max, struct handshake_crystal *cr, double *a0,
                                     struct err *e)
{
    memset(cr, 0, sizeof *cr);
    snprintf(cr->element, sizeof cr->element, "%s", element);
    for (int k = 0; k < pot->nelements; k++)
        if (strcmp(pot->element[k], element) == 0)
            cr->mass = pot->mass[k];
    if (!(cr->mass > 0))
        cr->mass = element_mass(element);
    if (!(cr->mass > 0))
        return err_set(e, ERR_INPUT, "no mass for element '%s'", element);
    struct crystal_spec spec = {LATTICE_FCC, cr->element, cr->mass, 3};
    double ecoh;
    int rc = crystal_equilibrium(pot, &spec, a_min, a_max, a0, &ecoh, e);
    if (!rc)
        rc = crystal_elastic_cubic(pot, &spec, *a0, &cr->c11, &cr->c12, &cr->c44, e);
    cr->pe_ref = -ecoh;
    return rc;
}
