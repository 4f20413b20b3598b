/* fuzz_sw: Stillinger-Weber files (pair_style sw), read for one element
 * (Si) and for two-element systems (Ga N, Cd Te) through potential_create;
 * a potential that builds computes the forces of a few atoms once. */
#include "fuzz/common.h"
#include "fuzz/fuzz.h"

int fuzz_sw_one(const uint8_t *data, size_t size)
{
    static const char *const si[] = {"Si"}, *const gan[] = {"Ga", "N"},
                             *const cdte[] = {"Cd", "Te"};
    static const double m_gan[] = {69.723, 14.007}, m_cdte[] = {112.41, 127.6};
    char dir[FUZZ_PATH_MAX], path[FUZZ_PATH_MAX + 64];
    fuzz_dir_create(dir, sizeof dir);
    fuzz_write(dir, "pot.sw", data, size, path, sizeof path);
    fuzz_potential("sw", path, si, NULL, 1);
    fuzz_potential("sw", path, gan, m_gan, 2);
    fuzz_potential("sw", path, cdte, m_cdte, 2);
    fuzz_dir_remove(dir);
    return 0;
}

FUZZ_ENTRY(sw)
