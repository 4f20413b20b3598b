/* mpm_units: conversion factors between a case's units and metal units. */
#include "mpm/mpm_units.h"

#include "core/units.h"

/* CODATA 2018 */
#define EV_J 1.602176634e-19
#define AMU_KG 1.66053906660e-27

void mpm_units_init(struct mpm_units *u, enum mpm_unit_system s)
{
    u->system = s;
    if (s == MPM_UNITS_SI) {
        u->name = "si";
        u->length = 1e10;                                /* m -> Å */
        u->time = 1e12;                                  /* s -> ps */
        u->velocity = 1e10 / 1e12;                       /* m/s -> Å/ps */
        u->density = 1.0 / UNITS_AMU_A3_TO_KG_M3;        /* kg/m^3 -> amu/Å^3 */
        u->stress = 1e-9 / UNITS_EVA3_TO_GPA;            /* Pa -> eV/Å^3 */
        u->energy = 1.0 / EV_J;                          /* J -> eV */
        u->mass = 1.0 / AMU_KG;                          /* kg -> amu */
        u->force = 1.0 / EV_J / 1e10;                    /* N = J/m -> eV/Å */
        u->momentum = u->mass * u->velocity;             /* kg m/s -> amu Å/ps */
        u->length_name = "m";
        u->time_name = "s";
        u->velocity_name = "m/s";
        u->density_name = "kg/m^3";
        u->stress_name = "Pa";
        u->energy_name = "J";
        u->mass_name = "kg";
        u->force_name = "N";
        u->momentum_name = "kg m/s";
        u->volume_name = "m^3";
    } else {
        u->name = "metal";
        u->length = 1.0;
        u->time = 1.0;
        u->velocity = 1.0;
        u->density = 1000.0 / UNITS_AMU_A3_TO_KG_M3;     /* g/cm^3 -> amu/Å^3 */
        u->stress = 1.0 / UNITS_EVA3_TO_GPA;             /* GPa -> eV/Å^3 */
        u->energy = 1.0;
        u->mass = 1.0;
        u->force = 1.0;
        u->momentum = 1.0;
        u->length_name = "Å";
        u->time_name = "ps";
        u->velocity_name = "Å/ps";
        u->density_name = "g/cm^3";
        u->stress_name = "GPa";
        u->energy_name = "eV";
        u->mass_name = "amu";
        u->force_name = "eV/Å";
        u->momentum_name = "amu Å/ps";
        u->volume_name = "Å^3";
    }
}
