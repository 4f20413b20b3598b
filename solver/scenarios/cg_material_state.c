/* cg_material_state: density and elastic constants of one lattice state. */
#include "scenarios/cg_material_state.h"

#include <math.h>
#include <stdio.h>

#include "dpd/cg_lattice.h"

const char *const cg_state_source_names[] = {"lattice", "bar", "parameter", "given", NULL};

int cg_material_state_get(const struct cg_params *prm, int source, double a_given, double T,
                          double bar_volume, struct cg_material_state *s, struct err *e)
{
    const double a0 = prm->lattice_constant;
    s->source = source;
    s->T = T;
    switch (source) {
    case CG_STATE_LATTICE:
        /* within 10 % of the parameter file's: the thermal pressure of a
         * solid moves it by a few per cent at most */
        if (cg_lattice_solve_pressure(&prm->sc, T, 1, 0.0, 0.9 * a0, 1.1 * a0, &s->a))
            return err_set(e, ERR_INPUT,
                           "no zero-pressure coarse-grained lattice at %.1f K within 10 %% of "
                           "%.4g Å: give concurrent.material_state: parameter or bar",
                           T, a0);
        snprintf(s->note, sizeof s->note,
                 "lattice: zero pressure (static + quasi-harmonic thermal) at %.1f K, a = %.5f Å",
                 T, s->a);
        break;
    case CG_STATE_BAR:
        s->a = cbrt(4 * bar_volume);
        snprintf(s->note, sizeof s->note,
                 "bar: volume per particle of the bar as read, %.4f Å^3, a = %.5f Å", bar_volume,
                 s->a);
        break;
    case CG_STATE_GIVEN:
        s->a = a_given;
        snprintf(s->note, sizeof s->note, "given: concurrent.lattice_constant, a = %.5f Å",
                 s->a);
        break;
    default:
        s->a = a0;
        snprintf(s->note, sizeof s->note, "parameter: the parameter file's a = %.5f Å", s->a);
        break;
    }
    s->volume = s->a * s->a * s->a / 4;
    s->rho = prm->mass / s->volume;
    cg_lattice_elastic(&prm->sc, s->a, &s->c11, &s->c12, &s->c44);
    return 0;
}
