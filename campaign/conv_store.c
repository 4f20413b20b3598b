/* conv_store: convergence rows in the database (see conv_store.h). */
#include "conv_store.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "db.h"
#include "sysinfo.h"

char *conv_store_list(const struct study_analysis *a, const struct sa_conv *c, int of_h)
{
    json_t *l = json_array();
    for (int i = 0; i < c->npts; i++) {
        const struct sa_point *pt = &a->pts[c->pts[i]];
        double x = of_h ? pt->h : pt->mean[c->metric];
        json_array_append_new(l, isfinite(x) ? json_real(x) : json_null());
    }
    char *t = json_dumps(l, JSON_COMPACT | JSON_REAL_PRECISION(17));
    json_decref(l);
    return t;
}

static void bind_num(sqlite3_stmt *st, int i, double x)
{
    if (isfinite(x))
        sqlite3_bind_double(st, i, x);
    else
        sqlite3_bind_null(st, i);
}

static int write_one(sqlite3_stmt *st, const struct study_analysis *a, const struct sa_conv *c,
                     const char *source, const char *now)
{
    const struct rdata *d = a->d;
    const struct conv_result *r = &c->c;
    int m = c->metric, ok = c->status == SA_OK;
    char *hl = conv_store_list(a, c, 1), *pl = conv_store_list(a, c, 0);
    sqlite3_reset(st);
    sqlite3_clear_bindings(st);
    sqlite3_bind_int64(st, 1, d->study_id);
    sqlite3_bind_text(st, 2, d->metric[m], -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 3, d->unit[m] && d->unit[m][0] ? d->unit[m] : "1", -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 4, a->groups[c->group].key, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 5, source, -1, SQLITE_STATIC);
    sqlite3_bind_text(st, 6, d->axes[a->res.axis].name, -1, SQLITE_STATIC);
    sqlite3_bind_int(st, 7, c->npts);
    sqlite3_bind_text(st, 8, hl ? hl : "[]", -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(st, 9, pl ? pl : "[]", -1, SQLITE_TRANSIENT);
    free(hl);
    free(pl);
    /* the three finest grids with a value (as the analysis took them) */
    for (int q = 0; q < 3; q++) {
        const struct sa_point *pt = &a->pts[c->pts[q]];
        sqlite3_bind_double(st, 10 + q, pt->h);
        bind_num(st, 13 + q, pt->mean[m]);
    }
    bind_num(st, 16, ok ? r->r21 : NAN);
    bind_num(st, 17, ok ? r->r32 : NAN);
    bind_num(st, 18, ok ? r->ratio : NAN);
    sqlite3_bind_text(st, 19, ok ? conv_kind_names[r->kind] : "error", -1, SQLITE_STATIC);
    bind_num(st, 20, ok ? r->p : NAN);
    bind_num(st, 21, ok ? r->phi_ext : NAN);
    bind_num(st, 22, ok ? r->e_a21 : NAN);
    bind_num(st, 23, ok ? r->e_ext21 : NAN);
    bind_num(st, 24, ok ? r->gci_fine : NAN);
    bind_num(st, 25, ok ? r->gci_medium : NAN);
    bind_num(st, 26, ok ? c->abs_unc : NAN);
    bind_num(st, 27, ok ? r->asymptotic : NAN);
    sqlite3_bind_int(st, 28, ok && r->kind == CONV_OSCILLATORY);
    sqlite3_bind_int(st, 29, ok && r->kind == CONV_DIVERGENT);
    sqlite3_bind_int(st, 30, strstr(c->flags, "not in the asymptotic range") != NULL);
    sqlite3_bind_text(st, 31, c->status == SA_ERROR && c->note[0] ? c->note : c->flags, -1,
                      SQLITE_STATIC);
    sqlite3_bind_text(st, 32, now, -1, SQLITE_STATIC);
    return sqlite3_step(st) == SQLITE_DONE ? 0 : -1;
}

int conv_store_write(sqlite3 *db, const struct study_analysis *a, const char *source, int *rows,
                     struct err *e)
{
    *rows = 0;
    if (!a->conv)
        return 0;
    char now[40];
    sys_iso_time(sys_now(), now, sizeof now);
    sqlite3_stmt *st;
    int rc = db_prepare(
        db,
        "INSERT INTO convergence (study_id, metric, unit, series, source, axis, levels, h, phi, "
        "h1, h2, h3, phi1, phi2, phi3, r21, r32, ratio, kind, p, phi_ext, e_a21, e_ext21, "
        "gci_fine, gci_medium, band, asymptotic, oscillatory, divergent, non_asymptotic, flags, "
        "computed) VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7, ?8, ?9, ?10, ?11, ?12, ?13, ?14, ?15, "
        "?16, ?17, ?18, ?19, ?20, ?21, ?22, ?23, ?24, ?25, ?26, ?27, ?28, ?29, ?30, ?31, ?32) "
        "ON CONFLICT (study_id, metric, series, source, h1, h2, h3) DO UPDATE SET "
        "unit = excluded.unit, axis = excluded.axis, levels = excluded.levels, h = excluded.h, "
        "phi = excluded.phi, phi1 = excluded.phi1, phi2 = excluded.phi2, phi3 = excluded.phi3, "
        "r21 = excluded.r21, r32 = excluded.r32, ratio = excluded.ratio, kind = excluded.kind, "
        "p = excluded.p, phi_ext = excluded.phi_ext, e_a21 = excluded.e_a21, "
        "e_ext21 = excluded.e_ext21, gci_fine = excluded.gci_fine, "
        "gci_medium = excluded.gci_medium, band = excluded.band, "
        "asymptotic = excluded.asymptotic, oscillatory = excluded.oscillatory, "
        "divergent = excluded.divergent, non_asymptotic = excluded.non_asymptotic, "
        "flags = excluded.flags, computed = excluded.computed",
        &st, e);
    if (rc)
        return rc;
    if ((rc = db_begin(db, e))) {
        sqlite3_finalize(st);
        return rc;
    }
    for (int k = 0; k < a->nmetrics && !rc; k++)
        for (int g = 0; g < a->ngroups && !rc; g++) {
            const struct sa_conv *c = sa_conv_at(a, k, g);
            if (c->npts < 3)
                continue;
            if (write_one(st, a, c, source, now) != 0)
                rc = db_fail(db, e, "writing the convergence table");
            else
                (*rows)++;
        }
    sqlite3_finalize(st);
    if (!rc)
        rc = db_commit(db, e);
    if (rc) {
        db_rollback(db);
        *rows = 0;
    }
    return rc;
}
