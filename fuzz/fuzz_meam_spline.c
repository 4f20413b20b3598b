/* fuzz_meam_spline: spline MEAM files (pair_style meam/spline, old and new
 * format) for silicon through potential_create; a potential that builds
 * computes the forces of a few atoms once. */
#include "fuzz/common.h"
#include "fuzz/fuzz.h"

int fuzz_meam_spline_one(const uint8_t *data, size_t size)
{
    static const char *const si[] = {"Si"};
    char dir[FUZZ_PATH_MAX], path[FUZZ_PATH_MAX + 64];
    fuzz_dir_create(dir, sizeof dir);
    fuzz_write(dir, "pot.meam.spline", data, size, path, sizeof path);
    fuzz_potential("meam/spline", path, si, NULL, 1);
    fuzz_dir_remove(dir);
    return 0;
}

FUZZ_ENTRY(meam_spline)
