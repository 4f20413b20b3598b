/* elements: facts about chemical elements the builders need. */
#ifndef CASCADE_ELEMENTS_H
#define CASCADE_ELEMENTS_H

/* Standard atomic mass (amu) of an element symbol, 0 when unknown. */
double element_mass(const char *symbol);

#endif
