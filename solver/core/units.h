/*
 * units: the solver works in LAMMPS "metal" units throughout:
 *   length Å, time ps, energy eV, mass amu (g/mol), temperature K,
 *   velocity Å/ps, force eV/Å, stress eV/Å^3 (GPa in reports).
 * Constants are CODATA 2018.
 */
#ifndef CASCADE_UNITS_H
#define CASCADE_UNITS_H

#define UNITS_KB 8.617333262e-5            /* Boltzmann constant, eV/K            */
#define UNITS_MVV2E 1.0364269656262175e-4  /* amu Å^2/ps^2 -> eV                 */
#define UNITS_FTM2V (1.0 / UNITS_MVV2E)    /* (eV/Å)/amu -> Å/ps^2                */
#define UNITS_EVA3_TO_GPA 160.21766208     /* eV/Å^3 -> GPa                       */
#define UNITS_AMU_A3_TO_KG_M3 1660.5390666 /* amu/Å^3 -> kg/m^3                   */
#define UNITS_APS_TO_MS 100.0              /* Å/ps -> m/s                         */

#endif
