/*
 * One state for the material points of the concurrent DPD/MPM model
 * (solver/scenarios/cg_material_state.h): density, point volume and cubic
 * elastic constants at the same lattice constant.
 *
 *   - lattice: the model pressure (static + quasi-harmonic thermal) at the
 *     found lattice constant vanishes (below 1e-6 GPa); at 298 K it is the
 *     parameter file's 7.2786 Å within 1e-3 Å (the fit's zero-pressure
 *     crystal at its temperature), at 0 K the static one (smaller, stiffer);
 *   - rho = 4 m / a^3 and the volume a^3 / 4 in every state, C at that a;
 *   - bar: a = (4 V)^(1/3) of the given volume per particle; parameter and
 *     given: those lattice constants; the note names the source.
 */
#include <criterion/criterion.h>
#include <math.h>
#include <string.h>

#include "core/units.h"
#include "dpd/cg_lattice.h"
#include "scenarios/cg_material_state.h"

static struct cg_params params(void)
{
    struct cg_params p;
    memset(&p, 0, sizeof p);
    p.sc = (struct sc_params){0.093945, 37.8271, 7.23, 9, 6, 10.845, 0, 0, 0, 0, 0, 0};
    sc_params_finish(&p.sc);
    p.mass = 508.368;
    p.atoms_per_particle = 8;
    p.lattice_constant = 7.2786;
    return p;
}

static void consistent(const struct cg_params *p, const struct cg_material_state *s)
{
    double c11, c12, c44;
    cg_lattice_elastic(&p->sc, s->a, &c11, &c12, &c44);
    cr_expect(fabs(s->c11 - c11) <= 1e-12 * c11 && fabs(s->c12 - c12) <= 1e-12 * c11 &&
              fabs(s->c44 - c44) <= 1e-12 * c11);
    cr_expect(fabs(s->volume - s->a * s->a * s->a / 4) < 1e-12 * s->volume);
    cr_expect(fabs(s->rho - p->mass / s->volume) < 1e-12 * s->rho);
}

Test(cg_material_state, lattice_state_at_the_run_temperature)
{
    struct cg_params p = params();
    struct cg_material_state s0, s298;
    struct err e = {0};
    cr_assert_eq(cg_material_state_get(&p, CG_STATE_LATTICE, 0, 298.0, 0, &s298, &e), 0, "%s",
                 e.msg);
    cr_assert_eq(cg_material_state_get(&p, CG_STATE_LATTICE, 0, 0.0, 0, &s0, &e), 0, "%s", e.msg);
    double P = cg_lattice_pressure(&p.sc, s298.a, 298.0, 1) * UNITS_EVA3_TO_GPA;
    cr_expect(fabs(P) < 1e-6, "pressure %g GPa", P);
    cr_expect(fabs(s298.a - 7.2786) < 1e-3, "a(298 K) = %.5f Å", s298.a);
    cr_expect(s0.a < s298.a && s0.c11 > s298.c11, "0 K: a %.5f C11 %g", s0.a, s0.c11);
    consistent(&p, &s298);
    consistent(&p, &s0);
    cr_expect(strstr(s298.note, "lattice") && strstr(s298.note, "298.0 K"), "%s", s298.note);
    /* sqrt(C11/rho) of the 298 K state: 4087 m/s (docs/dpd.md) */
    double cl = sqrt(s298.c11 / s298.rho * UNITS_FTM2V) * UNITS_APS_TO_MS;
    cr_expect(fabs(cl - 4087) < 1, "sqrt(C11/rho) %.1f m/s", cl);
}

Test(cg_material_state, bar_parameter_and_given_states)
{
    struct cg_params p = params();
    struct cg_material_state s;
    struct err e = {0};
    double vbar = 94.0;   /* Å^3: a denser bar than the crystal (96.40) */
    cr_assert_eq(cg_material_state_get(&p, CG_STATE_BAR, 0, 298.0, vbar, &s, &e), 0);
    cr_expect(fabs(s.a - cbrt(4 * vbar)) < 1e-12 && fabs(s.volume - vbar) < 1e-9);
    consistent(&p, &s);
    cr_expect(strstr(s.note, "bar") != NULL, "%s", s.note);
    cr_assert_eq(cg_material_state_get(&p, CG_STATE_PARAMETER, 0, 298.0, vbar, &s, &e), 0);
    cr_expect(s.a == 7.2786);
    consistent(&p, &s);
    cr_assert_eq(cg_material_state_get(&p, CG_STATE_GIVEN, 7.25, 298.0, vbar, &s, &e), 0);
    cr_expect(s.a == 7.25);
    consistent(&p, &s);
    cr_expect(strstr(s.note, "given") != NULL, "%s", s.note);
}
