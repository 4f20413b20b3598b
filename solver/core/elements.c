/* elements: standard atomic masses (IUPAC 2013 conventional values). */
#include "core/elements.h"

#include <string.h>

double element_mass(const char *s)
{
    static const struct {
        const char *sym;
        double m;
    } table[] = {{"H", 1.008},    {"He", 4.0026},  {"C", 12.011},   {"N", 14.007},
                 {"O", 15.999},   {"Ne", 20.180},  {"Al", 26.9815}, {"Si", 28.0855},
                 {"Ar", 39.948},  {"Ti", 47.867},  {"Fe", 55.845},  {"Ni", 58.6934},
                 {"Cu", 63.546},  {"Zn", 65.38},   {"Ga", 69.723},  {"Ge", 72.630},
                 {"Se", 78.971},  {"Kr", 83.798},  {"Mo", 95.95},   {"Ag", 107.8682},
                 {"Cd", 112.414}, {"Te", 127.60},  {"Hg", 200.592}, {"S", 32.06},
                 {"Ta", 180.94788}, {"W", 183.84},
                 {"Pt", 195.084}, {"Au", 196.96657}, {"Pb", 207.2}, {NULL, 0}};
    for (int i = 0; table[i].sym; i++)
        if (strcmp(table[i].sym, s) == 0)
            return table[i].m;
    return 0.0;
}

int element_known(const char *s)
{
    static const char *const sym[] = {
        "H",  "He", "Li", "Be", "B",  "C",  "N",  "O",  "F",  "Ne", "Na", "Mg", "Al", "Si", "P",
        "S",  "Cl", "Ar", "K",  "Ca", "Sc", "Ti", "V",  "Cr", "Mn", "Fe", "Co", "Ni", "Cu", "Zn",
        "Ga", "Ge", "As", "Se", "Br", "Kr", "Rb", "Sr", "Y",  "Zr", "Nb", "Mo", "Tc", "Ru", "Rh",
        "Pd", "Ag", "Cd", "In", "Sn", "Sb", "Te", "I",  "Xe", "Cs", "Ba", "La", "Ce", "Pr", "Nd",
        "Pm", "Sm", "Eu", "Gd", "Tb", "Dy", "Ho", "Er", "Tm", "Yb", "Lu", "Hf", "Ta", "W",  "Re",
        "Os", "Ir", "Pt", "Au", "Hg", "Tl", "Pb", "Bi", "Po", "At", "Rn", "Fr", "Ra", "Ac", "Th",
        "Pa", "U",  "Np", "Pu", "Am", "Cm", "Bk", "Cf", "Es", "Fm", "Md", "No", "Lr", "Rf", "Db",
        "Sg", "Bh", "Hs", "Mt", "Ds", "Rg", "Cn", "Nh", "Fl", "Mc", "Lv", "Ts", "Og", NULL};
    for (int i = 0; sym[i]; i++)
        if (strcmp(sym[i], s) == 0)
            return 1;
    return 0;
}
