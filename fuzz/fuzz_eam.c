/* fuzz_eam: DYNAMO EAM files -- funcfl (pair_style eam), setfl (eam/alloy)
 * and Finnis-Sinclair (eam/fs).  Every input is read in all three formats,
 * through potential_create as a case's `potential` section does, and a
 * potential that builds computes the forces of a few atoms once. */
#include "fuzz/common.h"
#include "fuzz/fuzz.h"

int fuzz_eam_one(const uint8_t *data, size_t size)
{
    static const char *const styles[] = {"eam", "eam/alloy", "eam/fs"};
    char dir[FUZZ_PATH_MAX], path[FUZZ_PATH_MAX + 64];
    fuzz_dir_create(dir, sizeof dir);
    fuzz_write(dir, "pot.eam", data, size, path, sizeof path);
    for (int k = 0; k < 3; k++)
        fuzz_potential(styles[k], path, NULL, NULL, 0);
    fuzz_dir_remove(dir);
    return 0;
}

FUZZ_ENTRY(eam)
