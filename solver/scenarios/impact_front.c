/* impact_front: probe samples and the front-fit report of the impacts. */
#include "scenarios/impact_front.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analysis/wave_front.h"
#include "core/halo.h"
#include "core/units.h"

/* the peak window: 15 % above sqrt(C11/rho) for the nonlinear speed-up */
#define WINDOW_SPEED_FACTOR 1.15
/* ps: a leading pulse's peak is the largest value within +- this (the
 * leading pulse of the flyer impacts rises over about 0.3 ps) */
#define PEAK_HALFWIDTH 0.1

/* accumulator slots per run: core np, section np, regions 2 */
#define SLOTS(f) (2 * (size_t)(f)->np + 2)

int impact_front_init(struct impact_front *f, int axis, double face, double length,
                      const double regions[2], double half, double w, const double lo[3],
                      const double extent[3], long cap, struct err *e)
{
    memset(f, 0, sizeof *f);
    f->axis = axis;
    f->face = face;
    f->length = length;
    f->w = w;
    f->x_first = regions[0] - 0.5 * w;
    f->np = (int)floor((regions[1] - regions[0]) / w + 1e-9) + 1;
    for (int r = 0; r < 2; r++) {
        f->reg_lo[r] = regions[r] - half;
        f->reg_hi[r] = regions[r] + half;
    }
    for (int d = 0; d < 3; d++) {
        f->core_lo[d] = lo[d] + 0.25 * extent[d];
        f->core_hi[d] = lo[d] + 0.75 * extent[d];
    }
    f->cap = cap;
    size_t slots = SLOTS(f);
    f->t = calloc((size_t)cap, sizeof *f->t);
    f->core = calloc((size_t)cap * f->np, sizeof *f->core);
    f->sect = calloc((size_t)cap * f->np, sizeof *f->sect);
    f->reg = calloc((size_t)cap * 2, sizeof *f->reg);
    f->sum = calloc(2 * slots, sizeof *f->sum);
    f->cnt = calloc(2 * slots, sizeof *f->cnt);
    if (!f->t || !f->core || !f->sect || !f->reg || !f->sum || !f->cnt) {
        impact_front_free(f);
        return err_nomem(e, "wave-front probes");
    }
    return 0;
}

void impact_front_free(struct impact_front *f)
{
    free(f->t);
    free(f->core);
    free(f->sect);
    free(f->reg);
    free(f->sum);
    free(f->cnt);
    memset(f, 0, sizeof *f);
}

void impact_front_clear(struct impact_front *f)
{
    size_t slots = SLOTS(f);
    memset(f->sum, 0, 2 * slots * sizeof *f->sum);
    memset(f->cnt, 0, 2 * slots * sizeof *f->cnt);
}

void impact_front_add(struct impact_front *f, int run, const double *x0, const double *v,
                      const uint32_t *mask, uint32_t exclude, long n)
{
    const int ax = f->axis, np = f->np;
    const size_t slots = SLOTS(f);
    double *sum = f->sum + (size_t)run * slots;
    long *cnt = f->cnt + (size_t)run * slots;
    for (long i = 0; i < n; i++) {
        if (mask && (mask[i] & exclude))
            continue;
        const double *r = x0 + 3 * i;
        double s = r[ax] - f->face, va = v[3 * i + ax];
        for (int q = 0; q < 2; q++)
            if (s >= f->reg_lo[q] && s < f->reg_hi[q]) {
                sum[2 * np + q] += va;
                cnt[2 * np + q]++;
            }
        double kf = floor((s - f->x_first) / f->w);
        if (kf < 0 || kf >= np)
            continue;
        int k = (int)kf;
        sum[np + k] += va;
        cnt[np + k]++;
        int core = 1;
        for (int d = 0; d < 3; d++)
            if (d != ax && (r[d] < f->core_lo[d] || r[d] >= f->core_hi[d]))
                core = 0;
        if (core) {
            sum[k] += va;
            cnt[k]++;
        }
    }
}

static double slot_signal(const struct impact_front *f, size_t q, int has_ref)
{
    const size_t slots = SLOTS(f);
    if (!f->cnt[q])
        return NAN;
    double a = f->sum[q] / (double)f->cnt[q];
    if (!has_ref)
        return a;
    return f->cnt[slots + q] ? a - f->sum[slots + q] / (double)f->cnt[slots + q] : NAN;
}

void impact_front_sum_ranks(struct impact_front *f, const struct halo *h)
{
    const size_t n = 2 * SLOTS(f);
    halo_sum(h, f->sum, (int)n);
    /* the counts in pieces through a double buffer (exact below 2^53) */
    double buf[64];
    for (size_t q0 = 0; q0 < n; q0 += 64) {
        int m = (int)(n - q0 < 64 ? n - q0 : 64);
        for (int q = 0; q < m; q++)
            buf[q] = (double)f->cnt[q0 + q];
        halo_sum(h, buf, m);
        for (int q = 0; q < m; q++)
            f->cnt[q0 + q] = lround(buf[q]);
    }
}

void impact_front_end(struct impact_front *f, double t, int has_ref)
{
    if (f->n >= f->cap)
        return;
    const int np = f->np;
    long j = f->n++;
    f->t[j] = t;
    for (int k = 0; k < np; k++) {
        f->core[j * np + k] = slot_signal(f, (size_t)k, has_ref);
        f->sect[j * np + k] = slot_signal(f, (size_t)(np + k), has_ref);
    }
    for (int q = 0; q < 2; q++)
        f->reg[2 * j + q] = slot_signal(f, (size_t)(2 * np + q), has_ref);
}

void impact_front_report(const struct impact_front *f, struct result *res, double c11, double c12,
                         double rho, double *speed)
{
    const int np = f->np;
    const long n = f->n;
    double cl = sqrt(c11 / rho * UNITS_FTM2V);   /* Å/ps */
    double e100 = (c11 - c12) * (c11 + 2 * c12) / (c11 + c12);
    double cb = e100 > 0 ? sqrt(e100 / rho * UNITS_FTM2V) : NAN;
    double *x = malloc((size_t)(np + 2) * 2 * sizeof *x);
    double *s1 = malloc((size_t)(n ? n : 1) * 2 * sizeof *s1);
    if (!x || !s1) {
        free(x);
        free(s1);
        if (speed)
            *speed = NAN;
        return;
    }
    double *tmax = x + np + 2, *s2 = s1 + (n ? n : 1);
    for (int k = 0; k < np; k++) {
        x[k] = f->x_first + (k + 0.5) * f->w;
        tmax[k] = (2 * f->length - x[k]) / (WINDOW_SPEED_FACTOR * cl);
    }
    /* the longitudinal front: core velocity; beside it the section
     * velocity */
    struct wave_front_result r, rs;
    wave_front_measure(f->t, n, f->core, np, x, tmax, PEAK_HALFWIDTH, &r);
    wave_front_measure(f->t, n, f->sect, np, x, tmax, PEAK_HALFWIDTH, &rs);
    struct wave_front_fit peak;
    wave_front_fit(f->t, n, f->core, np, x, tmax, PEAK_HALFWIDTH, 1.0, &peak);
    for (long j = 0; j < n; j++) {
        s1[j] = f->reg[2 * j];
        s2[j] = f->reg[2 * j + 1];
    }
    double rc1 = 0.5 * (f->reg_lo[0] + f->reg_hi[0]), rc2 = 0.5 * (f->reg_lo[1] + f->reg_hi[1]);
    double t1, t2;
    double va = wave_front_arrival_speed(
        f->t, n, s1, (2 * f->length - rc1) / (WINDOW_SPEED_FACTOR * cl), s2,
        (2 * f->length - rc2) / (WINDOW_SPEED_FACTOR * cl), PEAK_HALFWIDTH, rc2 - rc1,
        wave_front_fractions[WAVE_FRONT_PRIMARY], &t1, &t2);
    const double ms = UNITS_APS_TO_MS;
    result_metric(res, "wave_speed", r.speed * ms, "m/s");
    result_metric(res, "wave_speed_fit", r.speed_fit * ms, "m/s");
    result_metric(res, "wave_speed_stderr", r.stderr_ * ms, "m/s");
    result_metric(res, "wave_speed_spread", r.spread, "1");
    result_metric(res, "wave_speed_flag", (double)r.flag, "1");
    result_metric(res, "wave_speed_probes", (double)r.fit[WAVE_FRONT_PRIMARY].nprobes, "1");
    result_metric(res, "wave_speed_section", rs.speed_fit * ms, "m/s");
    result_metric(res, "wave_speed_section_spread", rs.spread, "1");
    result_metric(res, "wave_speed_rise_centroid", r.rise_centroid.speed * ms, "m/s");
    result_metric(res, "wave_front_broadening", r.broadening, "ps/Å");
    result_metric(res, "wave_front_broadening_stderr", r.broadening_stderr, "ps/Å");
    result_metric(res, "wave_front_rise_time", r.rise_time, "ps");
    /* the pulse centroids: the speed of the pulse's dominant long
     * wavelengths, the bar speed where the lateral surfaces are free */
    result_metric(res, "wave_speed_pulse_centroid", rs.pulse_centroid.speed * ms, "m/s");
    result_metric(res, "wave_speed_pulse_centroid_stderr", rs.pulse_centroid.stderr_ * ms,
                  "m/s");
    result_metric(res, "wave_speed_pulse_centroid_core", r.pulse_centroid.speed * ms, "m/s");
    result_metric(res, "wave_speed_peak", peak.speed * ms, "m/s");
    result_metric(res, "wave_speed_arrival", va * ms, "m/s");
    result_metric(res, "arrival_front_1", t1, "ps");
    result_metric(res, "arrival_front_2", t2, "ps");
    result_metric(res, "longitudinal_speed", cl * ms, "m/s");
    result_metric(res, "bar_speed", cb * ms, "m/s");
    double v[WAVE_FRONT_NFRAC], se[WAVE_FRONT_NFRAC], vs[WAVE_FRONT_NFRAC];
    for (int q = 0; q < WAVE_FRONT_NFRAC; q++) {
        v[q] = r.fit[q].speed * ms;
        se[q] = r.fit[q].stderr_ * ms;
        vs[q] = rs.fit[q].speed * ms;
    }
    result_series(res, "front_fractions", wave_front_fractions, WAVE_FRONT_NFRAC, "1");
    result_series(res, "wave_speed_fractions", v, WAVE_FRONT_NFRAC, "m/s");
    result_series(res, "wave_speed_fractions_stderr", se, WAVE_FRONT_NFRAC, "m/s");
    result_series(res, "wave_speed_section_fractions", vs, WAVE_FRONT_NFRAC, "m/s");
    result_series(res, "front_probe_x", x, np, "Å");
    if (speed)
        *speed = r.speed;
    free(x);
    free(s1);
}

int impact_front_checkpoint_write(const struct impact_front *f, struct ckpt *ck)
{
    int rc = ckpt_put_doubles(ck, "front_time", f->t, f->n);
    if (!rc) rc = ckpt_put_doubles(ck, "front_core", f->core, f->n * f->np);
    if (!rc) rc = ckpt_put_doubles(ck, "front_section", f->sect, f->n * f->np);
    if (!rc) rc = ckpt_put_doubles(ck, "front_regions", f->reg, f->n * 2);
    return rc;
}

int impact_front_checkpoint_read(struct impact_front *f, struct ckpt *ck, struct err *e)
{
    long n = ckpt_len(ck, "front_time");
    if (n < 0)
        return ERR_INPUT;
    if (n > f->cap)
        return err_set(e, ERR_INPUT, "%s: checkpoint has %ld front samples, at most %ld fit",
                       ck->path, n, f->cap);
    int rc = ckpt_get_doubles(ck, "front_time", f->t, n);
    if (!rc) rc = ckpt_get_doubles(ck, "front_core", f->core, n * f->np);
    if (!rc) rc = ckpt_get_doubles(ck, "front_section", f->sect, n * f->np);
    if (!rc) rc = ckpt_get_doubles(ck, "front_regions", f->reg, n * 2);
    if (!rc)
        f->n = n;
    return rc;
}
