/*
 * mpm_units: the unit systems an MPM case may be written in.
 *
 * The solver computes in LAMMPS metal units (Å, ps, eV, amu; stress eV/Å^3).
 * Continuum problems are often stated in SI, so an `mpm` case chooses
 * `units: metal` or `units: si`; every dimensional key of the case is read in
 * that system and converted here, and the run's outputs (result.json,
 * thermo.csv, HDF5 fields) are written back in it, each with its unit name.
 *
 *   quantity   metal      si
 *   length     Å          m
 *   time       ps         s
 *   velocity   Å/ps       m/s
 *   density    g/cm^3     kg/m^3      (g/cm^3 as in LAMMPS metal)
 *   stress     GPa        Pa          (moduli, tractions, yield stress)
 *   energy     eV         J
 *   mass       amu        kg
 *   force      eV/Å       N
 *   momentum   amu Å/ps   kg m/s
 */
#ifndef CASCADE_MPM_UNITS_H
#define CASCADE_MPM_UNITS_H

enum mpm_unit_system { MPM_UNITS_METAL, MPM_UNITS_SI };

/* Factors multiply a value in the case's units to give the internal value. */
struct mpm_units {
    enum mpm_unit_system system;
    double length, time, velocity, density, stress, energy, mass, force, momentum;
    const char *length_name, *time_name, *velocity_name, *density_name, *stress_name,
        *energy_name, *mass_name, *force_name, *momentum_name, *volume_name;
    const char *name;   /* "metal" or "si" */
};

void mpm_units_init(struct mpm_units *u, enum mpm_unit_system s);

#endif
