/* box: boundary handling and geometry of the (restricted triclinic) cell. */
#include "core/box.h"

#include <math.h>
#include <stdio.h>

const char *const boundary_names[] = {"periodic", "free", "fixed", NULL};

double box_volume(const struct box *b)
{
    return box_length(b, 0) * box_length(b, 1) * box_length(b, 2);
}

void box_cell_matrix(const struct box *b, double h[3][3])
{
    double lx = box_length(b, 0), ly = box_length(b, 1), lz = box_length(b, 2);
    const double *t = b->tilt;
    h[0][0] = lx, h[0][1] = t[0], h[0][2] = t[1];
    h[1][0] = 0, h[1][1] = ly, h[1][2] = t[2];
    h[2][0] = 0, h[2][1] = 0, h[2][2] = lz;
}

double box_height(const struct box *b, int d)
{
    if (!box_tilted(b))
        return box_length(b, d);
    double lx = box_length(b, 0), ly = box_length(b, 1), lz = box_length(b, 2);
    double xy = b->tilt[0], xz = b->tilt[1], yz = b->tilt[2];
    if (d == 2)   /* V / |a x b| */
        return lz;
    if (d == 1)   /* V / |c x a|, c x a = lx (0, lz, -yz) */
        return ly * lz / sqrt(lz * lz + yz * yz);
    /* V / |b x c|, b x c = (ly lz, -xy lz, xy yz - ly xz) */
    double cx = ly * lz, cy = -xy * lz, cz = xy * yz - ly * xz;
    return lx * ly * lz / sqrt(cx * cx + cy * cy + cz * cz);
}

void box_to_fractional(const struct box *b, const double x[3], double s[3])
{
    double lx = box_length(b, 0), ly = box_length(b, 1), lz = box_length(b, 2);
    s[2] = (x[2] - b->lo[2]) / lz;
    s[1] = (x[1] - b->lo[1] - b->tilt[2] * s[2]) / ly;
    s[0] = (x[0] - b->lo[0] - b->tilt[0] * s[1] - b->tilt[1] * s[2]) / lx;
}

void box_image_shift(const struct box *b, const int n[3], double out[3])
{
    out[0] = n[0] * box_length(b, 0) + n[1] * b->tilt[0] + n[2] * b->tilt[1];
    out[1] = n[1] * box_length(b, 1) + n[2] * b->tilt[2];
    out[2] = n[2] * box_length(b, 2);
}

void box_min_image(const struct box *b, double dx[3])
{
    /* z first: the c edge moves x and y too; then y (b moves x); then x.
     * With tilt 0 0 0 this is dx -= L round(dx / L) per axis. */
    if (b->bc[2] == BOUNDARY_PERIODIC) {
        double k = round(dx[2] / box_length(b, 2));
        if (k != 0) {
            dx[0] -= k * b->tilt[1];
            dx[1] -= k * b->tilt[2];
            dx[2] -= k * box_length(b, 2);
        }
    }
    if (b->bc[1] == BOUNDARY_PERIODIC) {
        double k = round(dx[1] / box_length(b, 1));
        if (k != 0) {
            dx[0] -= k * b->tilt[0];
            dx[1] -= k * box_length(b, 1);
        }
    }
    if (b->bc[0] == BOUNDARY_PERIODIC)
        dx[0] -= box_length(b, 0) * round(dx[0] / box_length(b, 0));
}

int box_check_tilt(const struct box *b, char *why, size_t len)
{
    static const char *const name[3] = {"xy", "xz", "yz"};
    /* LAMMPS: xy and xz against lx, yz against ly */
    static const int against[3] = {0, 0, 1};
    if (!box_tilted(b))
        return 0;
    for (int d = 0; d < 3; d++) {
        double h = box_height(b, d);
        if (!(h > 0 && isfinite(h) && box_length(b, d) > 0 && isfinite(box_length(b, d)))) {
            snprintf(why, len, "the tilted cell is degenerate: %g Å high across its %c faces",
                     h, "abc"[d]);
            return -1;
        }
    }
    for (int q = 0; q < 3; q++) {
        double l = box_length(b, against[q]);
        if (!(fabs(b->tilt[q]) <= 0.5 * l)) {
            snprintf(why, len, "tilt %s = %.10g is more than half the box length l%c = %.10g "
                     "(LAMMPS' limit: the same lattice has a less skewed cell, tilt %s %+.10g "
                     "l%c)", name[q], b->tilt[q], "xyz"[against[q]], l, name[q],
                     b->tilt[q] > 0 ? -1.0 : 1.0, "xyz"[against[q]]);
            return -1;
        }
    }
    for (int d = 0; d < 3; d++)
        if (b->bc[d] != BOUNDARY_PERIODIC) {
            snprintf(why, len, "a tilted box (xy xz yz = %g %g %g) is simulated periodic along "
                     "x, y and z only; %c is %s", b->tilt[0], b->tilt[1], b->tilt[2], "xyz"[d],
                     boundary_names[b->bc[d]]);
            return -1;
        }
    return 0;
}

/* The triclinic remap: fractional coordinates wrapped into [0, 1), the
 * image flags counting the edges moved (as LAMMPS' Domain::remap in lamda
 * coordinates).  Every axis is periodic (box_check_tilt). */
static int remap_tilted(const struct box *b, struct particles *p, struct err *e)
{
    for (int d = 0; d < 3; d++)
        if (b->bc[d] != BOUNDARY_PERIODIC)
            return err_set(e, ERR_INPUT, "a tilted box must be periodic along x, y and z (%c is "
                           "%s)", "xyz"[d], boundary_names[b->bc[d]]);
    for (int i = 0; i < p->n_owned; i++) {
        double *x = p->x + 3 * i, s[3];
        box_to_fractional(b, x, s);
        int k[3], any = 0;
        for (int d = 0; d < 3; d++) {
            double f = floor(s[d]);
            if (!(fabs(f) < 1.0e6))
                return err_set(e, ERR_DIVERGED,
                               "particle id %lld at (%g, %g, %g) is %s the periodic tilted box",
                               (long long)p->id[i], x[0], x[1], x[2],
                               isfinite(s[d]) ? "a million box lengths outside" : "not inside");
            k[d] = (int)f;
            any |= k[d];
        }
        if (!any)
            continue;
        double sh[3];
        box_image_shift(b, k, sh);
        for (int d = 0; d < 3; d++) {
            x[d] -= sh[d];
            p->image[3 * i + d] += k[d];
        }
        /* round-off at an upper face: one more edge, as the orthogonal
         * remap counts one more image there */
        box_to_fractional(b, x, s);
        int up[3] = {s[0] >= 1.0, s[1] >= 1.0, s[2] >= 1.0};
        if (up[0] | up[1] | up[2]) {
            box_image_shift(b, up, sh);
            for (int d = 0; d < 3; d++) {
                x[d] -= sh[d];
                p->image[3 * i + d] += up[d];
            }
        }
    }
    return 0;
}

int box_remap(struct box *b, struct particles *p, double margin, struct err *e)
{
    if (box_tilted(b))
        return remap_tilted(b, p, e);
    for (int d = 0; d < 3; d++) {
        double lo = b->lo[d], hi = b->hi[d], len = hi - lo;
        if (b->bc[d] == BOUNDARY_PERIODIC) {
            for (int i = 0; i < p->n_owned; i++) {
                double *x = &p->x[3 * i + d];
                if (*x < lo || *x >= hi) {
                    double k = floor((*x - lo) / len);
                    /* a NaN or a particle a million boxes away is a runaway,
                     * not an image to count (and (int)k would overflow) */
                    if (!(fabs(k) < 1.0e6))
                        return err_set(e, ERR_DIVERGED,
                                       "particle id %lld has %c = %g, %s the periodic box "
                                       "[%g, %g)", (long long)p->id[i], "xyz"[d], *x,
                                       isfinite(*x) ? "a million box lengths outside" : "not inside",
                                       lo, hi);
                    *x -= k * len;
                    if (*x >= hi) {
                        /* round-off at the upper face: an atom a hair below
                         * lo lands on hi, which is lo of the next image, so
                         * the image count is one more (else the unwrapped
                         * position jumps by a box length) */
                        *x = lo;
                        k += 1;
                    }
                    p->image[3 * i + d] += (int)k;
                }
            }
        } else if (b->bc[d] == BOUNDARY_FREE) {
            double mn = INFINITY, mx = -INFINITY;
            for (int i = 0; i < p->n_owned; i++) {
                double x = p->x[3 * i + d];
                if (x < mn) mn = x;
                if (x > mx) mx = x;
            }
            if (p->n_owned > 0) {
                b->lo[d] = mn - margin;
                b->hi[d] = mx + margin;
            }
        } else {
            for (int i = 0; i < p->n_owned; i++) {
                double x = p->x[3 * i + d];
                if (!(x >= lo && x <= hi))
                    return err_set(e, ERR_RUNTIME,
                                   "particle %lld left the box through the fixed %c boundary "
                                   "(%c = %g Å, box [%g, %g])",
                                   (long long)p->id[i], "xyz"[d], "xyz"[d], x, lo, hi);
            }
        }
    }
    return 0;
}

void box_unwrap(const struct box *b, const struct particles *p, int i, double out[3])
{
    if (box_tilted(b)) {
        double sh[3];
        box_image_shift(b, p->image + 3 * i, sh);
        for (int d = 0; d < 3; d++)
            out[d] = p->x[3 * i + d] + sh[d];
        return;
    }
    for (int d = 0; d < 3; d++)
        out[d] = p->x[3 * i + d] + p->image[3 * i + d] * box_length(b, d);
}
