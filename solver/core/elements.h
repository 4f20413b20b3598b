/* elements: facts about chemical elements the builders need. */
#ifndef CASCADE_ELEMENTS_H
#define CASCADE_ELEMENTS_H

/* Standard atomic mass (amu) of an element symbol, 0 when unknown. */
double element_mass(const char *symbol);

/* 1 when symbol is one of the 118 chemical element symbols (case as in
 * "Cu"), whether or not its mass is in the table above. */
int element_known(const char *symbol);

#endif
