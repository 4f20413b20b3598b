/* decomp_record: result.json's `parallel` record (decomp_record.h). */
#include "output/decomp_record.h"

#include <jansson.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/parallel.h"

/* Peak resident memory of this process (kB; VmHWM of /proc/self/status,
 * 0 where there is none). */
static long peak_rss_kb(void)
{
    FILE *f = fopen("/proc/self/status", "r");
    long kb = 0;
    char line[256];
    while (f && fgets(line, sizeof line, f))
        if (sscanf(line, "VmHWM: %ld kB", &kb) == 1)
            break;
    if (f)
        fclose(f);
    return kb;
}

/* The `parallel` object of the result (made when missing), NULL without
 * memory. */
static json_t *parallel_record(struct result *res)
{
    json_t *rec = json_object_get(res->root, "parallel");
    if (rec)
        return rec;
    rec = json_object();
    if (rec && json_object_set_new(res->root, "parallel", rec) != 0)
        return NULL;
    return rec;
}

void decomp_record_write(struct run *run, const struct halo *h, const struct particles *p)
{
    decomp_record_write_counts(run, h->dc.par, h->dc.grid, p->n_owned);
    struct decomp_balance_record b = {h->balance_every, h->balance_threshold, h->balance_checks,
                                      h->balance_shifts, h->balance_worst};
    decomp_record_add_balance(&run->result, &b);
}

void decomp_record_add_balance(struct result *res, const struct decomp_balance_record *b)
{
    json_t *rec = b->every > 0 ? parallel_record(res) : NULL;
    if (!rec)
        return;
    json_object_set_new(rec, "balance_every", json_integer((json_int_t)b->every));
    json_object_set_new(rec, "balance_threshold", json_real(b->threshold));
    json_object_set_new(rec, "balance_checks", json_integer((json_int_t)b->checks));
    json_object_set_new(rec, "balance_shifts", json_integer((json_int_t)b->shifts));
    json_object_set_new(rec, "imbalance_worst_at_checks", json_real(b->worst));
}

/* A per-rank count under `key` and its max/mean imbalance under
 * `imbalance_key` (collective: mine is this rank's). */
static void add_counts(struct result *res, const struct parallel *par, const char *key,
                       const char *imbalance_key, long mine)
{
    int n = par ? par->size : 1;
    long *counts = malloc((size_t)n * sizeof *counts);
    if (!counts)
        return;
    parallel_allgather_long(par, mine, counts);
    json_t *rec = parallel_record(res);
    if (!rec) {
        free(counts);
        return;
    }
    json_t *per = json_array();
    long max = 0, sum = 0;
    for (int r = 0; r < n; r++) {
        json_array_append_new(per, json_integer((json_int_t)counts[r]));
        max = counts[r] > max ? counts[r] : max;
        sum += counts[r];
    }
    free(counts);
    double mean = (double)sum / n;
    json_object_set_new(rec, key, per);
    json_object_set_new(rec, imbalance_key, json_real(mean > 0 ? max / mean : 1.0));
}

void decomp_record_write_counts(struct run *run, const struct parallel *par, const int grid[3],
                                long owned)
{
    int n = par ? par->size : 1;
    add_counts(&run->result, par, "particles_per_rank", "imbalance_max_over_mean", owned);
    long *rss_kb = malloc((size_t)n * sizeof *rss_kb);
    if (!rss_kb)
        return;
    parallel_allgather_long(par, peak_rss_kb(), rss_kb);
    json_t *rss = json_array();
    for (int r = 0; r < n; r++)
        json_array_append_new(rss, json_real((double)rss_kb[r] / 1024.0));
    free(rss_kb);
    json_t *rec = parallel_record(&run->result);
    if (!rec) {
        json_decref(rss);
        return;
    }
    json_object_set_new(rec, "decomposition", json_string("bricks"));
    json_object_set_new(rec, "ranks", json_integer(n));
    json_object_set_new(rec, "grid", json_pack("[iii]", grid[0], grid[1], grid[2]));
    json_object_set_new(rec, "peak_rss_mib_per_rank", rss);
}

void decomp_record_add_counts(struct result *res, const struct parallel *par, const char *key,
                              long mine)
{
    char name[128];
    snprintf(name, sizeof name, "%s_imbalance_max_over_mean", key);
    add_counts(res, par, key, name, mine);
}

void decomp_record_add_integer(struct result *res, const char *key, long value)
{
    json_t *rec = parallel_record(res);
    if (rec)
        json_object_set_new(rec, key, json_integer((json_int_t)value));
}

void decomp_record_add_cell_tables(struct result *res, const struct parallel *par, long ncell,
                                   long made)
{
    decomp_record_add_integer(res, "mpm_cells", ncell);
    decomp_record_add_counts(res, par, "mpm_cell_tables_per_rank", made);
}
