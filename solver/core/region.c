/* region: point-in-region tests and their case-file reader. */
#include "core/region.h"

#include <math.h>

static int inside(const struct region *r, const double x[3])
{
    switch (r->shape) {
    case REGION_BOX:
        return x[0] >= r->lo[0] && x[0] < r->hi[0] && x[1] >= r->lo[1] && x[1] < r->hi[1] &&
               x[2] >= r->lo[2] && x[2] < r->hi[2];
    case REGION_SPHERE: {
        double dx = x[0] - r->center[0], dy = x[1] - r->center[1], dz = x[2] - r->center[2];
        return dx * dx + dy * dy + dz * dz <= r->radius * r->radius;
    }
    case REGION_SLAB:
        return x[r->axis] >= r->lo[r->axis] && x[r->axis] < r->hi[r->axis];
    case REGION_CYLINDER: {
        int a = (r->axis + 1) % 3, b = (r->axis + 2) % 3;
        double da = x[a] - r->center[a], db = x[b] - r->center[b];
        return da * da + db * db <= r->radius * r->radius && x[r->axis] >= r->lo[r->axis] &&
               x[r->axis] < r->hi[r->axis];
    }
    }
    return 0;
}

int region_contains(const struct region *r, const double x[3])
{
    return inside(r, x) != r->outside;
}

void region_bounds(const struct region *r, double lo[3], double hi[3])
{
    for (int d = 0; d < 3; d++) {
        lo[d] = -INFINITY;
        hi[d] = INFINITY;
    }
    if (r->outside)
        return;
    switch (r->shape) {
    case REGION_BOX:
        for (int d = 0; d < 3; d++) {
            lo[d] = r->lo[d];
            hi[d] = r->hi[d];
        }
        break;
    case REGION_SPHERE:
        for (int d = 0; d < 3; d++) {
            lo[d] = r->center[d] - r->radius;
            hi[d] = r->center[d] + r->radius;
        }
        break;
    case REGION_SLAB:
        lo[r->axis] = r->lo[r->axis];
        hi[r->axis] = r->hi[r->axis];
        break;
    case REGION_CYLINDER:
        for (int d = 0; d < 3; d++) {
            lo[d] = r->center[d] - r->radius;
            hi[d] = r->center[d] + r->radius;
        }
        lo[r->axis] = r->lo[r->axis];
        hi[r->axis] = r->hi[r->axis];
        break;
    }
}

double region_volume(const struct region *r)
{
    if (r->outside)
        return INFINITY;
    switch (r->shape) {
    case REGION_BOX:
        return (r->hi[0] - r->lo[0]) * (r->hi[1] - r->lo[1]) * (r->hi[2] - r->lo[2]);
    case REGION_SPHERE:
        return 4.0 / 3.0 * M_PI * r->radius * r->radius * r->radius;
    case REGION_CYLINDER:
        return M_PI * r->radius * r->radius * (r->hi[r->axis] - r->lo[r->axis]);
    case REGION_SLAB:
        return INFINITY;
    }
    return INFINITY;
}

int region_read(struct cfg_obj *o, struct region *r)
{
    static const char *const shapes[] = {"box", "sphere", "slab", "cylinder", NULL};
    static const char *const axes[] = {"x", "y", "z", NULL};
    static const char *const sides[] = {"in", "out", NULL};
    int shape, side, rc;
    if ((rc = cfg_enum(o, "shape", NULL, shapes, &shape)))
        return rc;
    r->shape = (enum region_shape)shape;
    if ((rc = cfg_enum(o, "side", "in", sides, &side)))
        return rc;
    r->outside = side;
    switch (r->shape) {
    case REGION_BOX:
        if ((rc = cfg_reals(o, "lo", 3, NULL, CFG_ANY, r->lo)) ||
            (rc = cfg_reals(o, "hi", 3, NULL, CFG_ANY, r->hi)))
            return rc;
        for (int d = 0; d < 3; d++)
            if (!(r->hi[d] > r->lo[d]))
                return cfg_error_at(o->cfg, o->path, "box region has hi[%d] = %g <= lo[%d] = %g",
                                    d, r->hi[d], d, r->lo[d]);
        break;
    case REGION_SPHERE:
        if ((rc = cfg_reals(o, "center", 3, NULL, CFG_ANY, r->center)) ||
            (rc = cfg_real(o, "radius", CFG_REQUIRED, CFG_GT(0), &r->radius)))
            return rc;
        break;
    case REGION_SLAB:
    case REGION_CYLINDER: {
        double lo, hi;
        if ((rc = cfg_enum(o, "axis", NULL, axes, &r->axis)) ||
            (rc = cfg_real(o, "lo", CFG_REQUIRED, CFG_ANY, &lo)) ||
            (rc = cfg_real(o, "hi", CFG_REQUIRED, CFG_ANY, &hi)))
            return rc;
        if (!(hi > lo))
            return cfg_error_at(o->cfg, o->path, "hi = %g must be greater than lo = %g", hi, lo);
        r->lo[r->axis] = lo;
        r->hi[r->axis] = hi;
        if (r->shape == REGION_CYLINDER) {
            double c2[2];
            if ((rc = cfg_reals(o, "center", 2, NULL, CFG_ANY, c2)) ||
                (rc = cfg_real(o, "radius", CFG_REQUIRED, CFG_GT(0), &r->radius)))
                return rc;
            r->center[(r->axis + 1) % 3] = c2[0];
            r->center[(r->axis + 2) % 3] = c2[1];
        }
        break;
    }
    }
    return cfg_close(o);
}
