/* config_read: LAMMPS data and extended XYZ readers (rules in config_read.h). */
#include "input/config_read.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/textfile.h"
#include "core/elements.h"
#include "core/units.h"

struct config_rules config_rules_default(void)
{
    struct config_rules r = {{BOUNDARY_PERIODIC, BOUNDARY_PERIODIC, BOUNDARY_PERIODIC},
                             CONFIG_MAX_ATOMS_DEFAULT, CONFIG_MIN_DISTANCE_DEFAULT, 1, NULL};
    return r;
}

static int starts_with_word(const char *line, const char *word)
{
    const char *s = line + strspn(line, " \t");
    size_t n = strlen(word);
    return strncmp(s, word, n) == 0 && (s[n] == '\0' || isspace((unsigned char)s[n]) || s[n] == '#');
}

static int cmp_id_pair(const void *a, const void *b)
{
    const int64_t *x = a, *y = b;
    if (x[0] != y[0])
        return (x[0] > y[0]) - (x[0] < y[0]);
    return (x[1] > y[1]) - (x[1] < y[1]);
}

/* Up to n whitespace-separated numbers of s, each parsed strictly
 * (text_parse_real).  Returns how many were read (n + 1 when s has more
 * than n), or -(k+1) when token k is not a finite decimal number (its text
 * in *bad). */
static int parse_doubles(const char *s, double *out, int n, char *bad, size_t badlen)
{
    int k = 0;
    while (k <= n) {
        s += strspn(s, " \t\r");
        if (!*s)
            break;
        if (k == n)
            return n + 1;
        size_t len = strcspn(s, " \t\r");
        char tok[128];
        snprintf(tok, sizeof tok, "%.*s", (int)(len < sizeof tok ? len : sizeof tok - 1), s);
        if (len >= sizeof tok || text_parse_real(tok, &out[k]) != 0) {
            if (bad)
                snprintf(bad, badlen, "%.40s%s", tok, len > 40 ? "..." : "");
            return -(k + 1);
        }
        s += len;
        k++;
    }
    return k;
}

/* Split s (modified) into at most max whitespace-separated tokens; returns
 * their number, max + 1 when there are more. */
static int split_tokens(char *s, char **tok, int max)
{
    int n = 0;
    char *save = NULL;
    for (char *w = strtok_r(s, " \t\r", &save); w; w = strtok_r(NULL, " \t\r", &save)) {
        if (n == max)
            return max + 1;
        tok[n++] = w;
    }
    return n;
}

/* --- checks shared by both readers --------------------------------------- */

/* The file line of each atom a reader added, for messages. */
struct atom_lines {
    int *line;
    long n, cap;
};

static int atom_lines_push(struct atom_lines *al, int line, struct err *e)
{
    if (al->n == al->cap) {
        long cap = al->cap ? 2 * al->cap : 1024;
        int *nl = realloc(al->line, (size_t)cap * sizeof *nl);
        if (!nl)
            return err_nomem(e, "atom lines");
        al->line = nl;
        al->cap = cap;
    }
    al->line[al->n++] = line;
    return 0;
}

/* The coordinate rule of config_read.h for one atom: names file:line, the
 * atom and the box when it is broken.  Positions are not moved here: the
 * first neighbour-list build wraps periodic axes (box_remap, counting the
 * images), and set-ups that look at the configuration before (a flyer
 * sized on the target's extent) see the file's numbers. */
static int check_position(struct textfile *t, const struct config_rules *r, const struct box *b,
                          long id, const double x[3], struct err *e)
{
    if (box_tilted(b)) {   /* all periodic (box_check_tilt): the same rule on s */
        double s[3];
        box_to_fractional(b, x, s);
        for (int d = 0; d < 3; d++)
            if (!(s[d] >= -1.0 && s[d] < 2.0))
                return textfile_error(t, e, "atom id %ld at (%.10g, %.10g, %.10g) is more than "
                                      "one cell edge %c outside the tilted box (fractional "
                                      "coordinate %.10g)", id, x[0], x[1], x[2], "abc"[d], s[d]);
        return 0;
    }
    for (int d = 0; d < 3; d++) {
        double lo = b->lo[d], hi = b->hi[d], len = hi - lo;
        char ax = "xyz"[d];
        if (r->bc[d] == BOUNDARY_FIXED) {
            if (!(x[d] >= lo && x[d] <= hi))
                return textfile_error(t, e, "atom id %ld: %c = %.10g is outside the box [%g, %g] "
                                      "(fixed boundary along %c)", id, ax, x[d], lo, hi, ax);
        } else if (!(x[d] >= lo - len && x[d] < hi + len)) {
            return textfile_error(t, e, "atom id %ld: %c = %.10g is more than one box length "
                                  "outside the box [%g, %g) (%s boundary along %c)",
                                  id, ax, x[d], lo, hi, boundary_names[r->bc[d]], ax);
        }
    }
    return 0;
}

/* Atom ids of particles base.. are unique; a repeat names both lines (the
 * repeat met first in the file). */
static int check_unique_ids(struct textfile *t, const struct particles *p, int base,
                            const struct atom_lines *al, const char *what, struct err *e)
{
    long n = p->n_owned - base;
    if (n < 2)
        return 0;
    int64_t (*pairs)[2] = malloc((size_t)n * sizeof *pairs);
    if (!pairs)
        return err_nomem(e, "atom id check");
    for (long i = 0; i < n; i++) {
        pairs[i][0] = p->id[base + i];
        pairs[i][1] = i;
    }
    qsort(pairs, (size_t)n, sizeof *pairs, cmp_id_pair);
    long first = -1, again = -1;
    for (long k = 1; k < n; k++)
        if (pairs[k][0] == pairs[k - 1][0] && (again < 0 || pairs[k][1] < again)) {
            /* pairs are in file order within one id: [k-1] is the earlier */
            again = (long)pairs[k][1];
            first = (long)pairs[k - 1][1];
        }
    free(pairs);
    if (again < 0)
        return 0;
    return textfile_error_at(t, al->line[again], e, "%s: atom id %lld is given twice (also at "
                             "line %d)", what, (long long)p->id[base + again], al->line[first]);
}

/* Two atoms of base.. closer than r->min_distance (minimum image along
 * periodic axes): a cell sort with cells of edge >= min_distance and about
 * one atom each, so O(N).  Names the pair whose later atom comes first in
 * the file. */
static int check_close_atoms(struct textfile *t, const struct particles *p, int base,
                             const struct box *b, const struct config_rules *r,
                             const struct atom_lines *al, struct err *e)
{
    int n = p->n_owned - base;
    double dmin = r->min_distance;
    if (n < 2 || !(dmin > 0))
        return 0;
    const double *x = p->x + 3 * (size_t)base;
    /* a tilted box (all periodic) is sorted on the fractional coordinates
     * times the cell's heights: an orthogonal box of the same volume whose
     * cells of edge >= w hold every pair closer than w in neighbour cells */
    const int tilted = box_tilted(b);
    double *bx = NULL;
    if (tilted) {
        bx = malloc((size_t)3 * n * sizeof *bx);
        if (!bx)
            return err_nomem(e, "close atom check");
        double hgt[3] = {box_height(b, 0), box_height(b, 1), box_height(b, 2)};
        for (int i = 0; i < n; i++) {
            double f[3];
            box_to_fractional(b, x + 3 * i, f);
            for (int d = 0; d < 3; d++)
                bx[3 * i + d] = f[d] * hgt[d];
        }
    }
    const double *xb = tilted ? bx : x;
    double lo[3], len[3], ext[3], vol = 1;
    int per[3], nc[3];
    for (int d = 0; d < 3; d++) {
        per[d] = r->bc[d] == BOUNDARY_PERIODIC;
        if (tilted) {
            lo[d] = 0;
            len[d] = box_height(b, d);
        } else if (per[d]) {
            lo[d] = b->lo[d];
            len[d] = b->hi[d] - b->lo[d];
        } else {   /* free or fixed: the atoms' own extent */
            double mn = x[d], mx = x[d];
            for (int i = 1; i < n; i++) {
                mn = fmin(mn, x[3 * i + d]);
                mx = fmax(mx, x[3 * i + d]);
            }
            lo[d] = mn;
            len[d] = mx - mn;
        }
        ext[d] = fmax(len[d], dmin);
        vol *= ext[d];
    }
    double w = fmax(dmin, cbrt(vol / n));
    long ncell = 1;
    for (int d = 0; d < 3; d++) {
        /* floor(ext / w) cells of edge >= w >= dmin: the product is at
         * most vol / w^3 <= n */
        double q = floor(ext[d] / w);
        nc[d] = q < 1 ? 1 : q > 1 << 20 ? 1 << 20 : (int)q;
        ncell *= nc[d];
    }
    int *start = calloc((size_t)ncell + 1, sizeof *start);
    int *cell = malloc((size_t)n * sizeof *cell);
    int *order = malloc((size_t)n * sizeof *order);
    if (!start || !cell || !order) {
        free(start);
        free(cell);
        free(order);
        free(bx);
        return err_nomem(e, "close atom check");
    }
    for (int i = 0; i < n; i++) {
        long c = 0;
        for (int d = 2; d >= 0; d--) {
            double u = xb[3 * i + d] - lo[d];
            if (per[d])   /* positions are not wrapped yet (up to a box length out) */
                u -= len[d] * floor(u / len[d]);
            double q = u / ext[d] * nc[d];
            int k = q < 0 ? 0 : q >= nc[d] - 1 ? nc[d] - 1 : (int)q;
            c = c * nc[d] + k;
        }
        cell[i] = (int)c;
        start[c + 1]++;
    }
    for (long c = 0; c < ncell; c++)
        start[c + 1] += start[c];
    int *fill = malloc((size_t)ncell * sizeof *fill);
    if (!fill) {
        free(start);
        free(cell);
        free(order);
        free(bx);
        return err_nomem(e, "close atom check");
    }
    memcpy(fill, start, (size_t)ncell * sizeof *fill);
    for (int i = 0; i < n; i++)
        order[fill[cell[i]]++] = i;
    free(fill);

    int hit_i = -1, hit_j = -1;
    double hit_r = 0;
    for (int i = 0; i < n && hit_i < 0; i++) {
        int ci[3];
        long c = cell[i];
        for (int d = 0; d < 3; d++) {
            ci[d] = (int)(c % nc[d]);
            c /= nc[d];
        }
        /* the distinct neighbour cells along each axis (fewer than 3 when
         * the axis has fewer cells) */
        int nb[3][3] = {{0}}, nnb[3];   /* initialised: gcc -O3 cannot see that only set entries are read */
        for (int d = 0; d < 3; d++) {
            nnb[d] = 0;
            for (int o = -1; o <= 1; o++) {
                int k = ci[d] + o;
                if (per[d])
                    k = (k + nc[d]) % nc[d];
                else if (k < 0 || k >= nc[d])
                    continue;
                int dup = 0;
                for (int q = 0; q < nnb[d]; q++)
                    dup |= nb[d][q] == k;
                if (!dup)
                    nb[d][nnb[d]++] = k;
            }
        }
        for (int a = 0; a < nnb[2]; a++)
            for (int bb = 0; bb < nnb[1]; bb++)
                for (int cc = 0; cc < nnb[0]; cc++) {
                    long cn = ((long)nb[2][a] * nc[1] + nb[1][bb]) * nc[0] + nb[0][cc];
                    for (int s = start[cn]; s < start[cn + 1]; s++) {
                        int j = order[s];
                        if (j >= i || (hit_j >= 0 && j > hit_j))
                            continue;
                        double r2 = 0, dv[3];
                        for (int d = 0; d < 3; d++) {
                            dv[d] = x[3 * i + d] - x[3 * j + d];
                            if (per[d] && !tilted)
                                dv[d] -= len[d] * nearbyint(dv[d] / len[d]);
                        }
                        if (tilted)   /* exact for dmin below half of lx, ly, lz */
                            box_min_image(b, dv);
                        for (int d = 0; d < 3; d++)
                            r2 += dv[d] * dv[d];
                        if (r2 < dmin * dmin) {
                            hit_i = i;
                            hit_j = j;
                            hit_r = sqrt(r2);
                        }
                    }
                }
    }
    free(start);
    free(cell);
    free(order);
    free(bx);
    if (hit_i < 0)
        return 0;
    const double *xi = x + 3 * hit_i;
    return textfile_error_at(t, al->line[hit_i], e, "atom id %lld at (%g, %g, %g) is %.3g Å from "
                             "atom id %lld at line %d: atoms closer than %g Å are taken for a "
                             "mistake", (long long)p->id[base + hit_i], xi[0], xi[1], xi[2], hit_r,
                             (long long)p->id[base + hit_j], al->line[hit_j], dmin);
}

static int check_atom_count(struct textfile *t, long n, const struct config_rules *r,
                            struct err *e)
{
    if (n > r->max_atoms)
        return textfile_error(t, e, "%ld atoms are more than the limit of %ld "
                              "(system.max_particles)", n, r->max_atoms);
    return 0;
}

/* --- LAMMPS data ---------------------------------------------------------- */

/* The tilt of a triclinic header (line tilt_line, 0: none) into b, refused
 * at that line when the caller's case type simulates orthogonal boxes only
 * (r->allow_tilt 0) or beyond LAMMPS' rules (box_check_tilt, with r->bc). */
static int accept_tilt(struct textfile *t, int tilt_line, const char *field, const double tilt[3],
                       const struct config_rules *r, struct box *b, struct err *e)
{
    struct box c = *b;
    for (int d = 0; d < 3; d++) {
        c.tilt[d] = tilt[d];
        c.bc[d] = r->bc[d];
    }
    if (!box_tilted(&c))
        return 0;   /* a prism of tilt 0 0 0 is the orthogonal box */
    if (!r->allow_tilt) {
        int q = tilt[0] != 0 ? 0 : tilt[1] != 0 ? 1 : 2;
        return textfile_error_at(t, tilt_line, e, "%s: tilt %s = %.10g: %s simulates "
                                 "orthogonal boxes only (tilt 0 0 0); a tilted box runs in "
                                 "type: md", field, (const char *const[]){"xy", "xz", "yz"}[q],
                                 tilt[q], r->who ? r->who : "this case type");
    }
    char why[512];
    if (box_check_tilt(&c, why, sizeof why) != 0)
        return textfile_error_at(t, tilt_line, e, "%s: %s", field, why);
    for (int d = 0; d < 3; d++)
        b->tilt[d] = tilt[d];
    return 0;
}

/* Header line "<count> words..." with the words given: 1 and the count, 0
 * when the words differ, -1 when they match but the count is not an
 * integer >= 0. */
/* A header line ends with its keyword (LAMMPS data format); section
 * keywords (Masses, Atoms, Velocities) are capitalised and stand alone. */
static int ends_with_header_keyword(const char *s)
{
    static const char *const kw[] = {"atoms", "types", "xhi", "yhi", "zhi", "yz"};
    size_t n = strlen(s);
    while (n > 0 && isspace((unsigned char)s[n - 1]))
        n--;
    size_t b = n;
    while (b > 0 && !isspace((unsigned char)s[b - 1]))
        b--;
    if (b == 0)
        return 0;   /* one word: a section keyword */
    for (size_t k = 0; k < sizeof kw / sizeof kw[0]; k++)
        if (n - b == strlen(kw[k]) && strncmp(s + b, kw[k], n - b) == 0)
            return 1;
    return 0;
}

static int header_count(char **tok, int ntok, const char *w1, const char *w2, long *out)
{
    int want = w2 ? 3 : 2;
    if (ntok != want || strcmp(tok[1], w1) != 0 || (w2 && strcmp(tok[2], w2) != 0))
        return 0;
    return text_parse_long(tok[0], out) == 0 && *out >= 0 ? 1 : -1;
}

int config_read_lammps_data(const char *path, const char *const *elements, int nelements,
                            const struct config_rules *rules, struct particles *p, struct box *b,
                            struct err *e)
{
    struct config_rules defrules = config_rules_default();
    const struct config_rules *r = rules ? rules : &defrules;
    struct textfile t;
    int rc = textfile_open(&t, path, e);
    if (rc)
        return rc;
    struct atom_lines al = {0};
    int *vline = NULL;   /* line of each atom's velocity, to find a repeat */
    const int base = p->n_owned;
    long natoms = -1, ntypes = -1;
    int have_box[3] = {0, 0, 0}, tilt_line = 0;
    double tilt[3] = {0, 0, 0};
    b->tilt[0] = b->tilt[1] = b->tilt[2] = 0;
    double masses[PARTICLES_MAX_TYPES] = {0};
    int mass_line[PARTICLES_MAX_TYPES] = {0};
    char names[PARTICLES_MAX_TYPES][16] = {{0}};
    char ex[TEXT_EXCERPT_SIZE];
    textfile_next_line(&t);   /* title */
    /* header: "N atoms", "M atom types", "lo hi xlo xhi", ...; counts of
     * molecular styles are read and ignored (atomic style has none) */
    static const char *const molecular[][2] = {
        {"bonds", NULL}, {"angles", NULL}, {"dihedrals", NULL}, {"impropers", NULL},
        {"bond", "types"}, {"angle", "types"}, {"dihedral", "types"}, {"improper", "types"}};
    while (textfile_next_line(&t) == 0) {
        char *hash = strchr(t.buf, '#');
        if (hash)
            *hash = '\0';
        const char *s = t.buf + strspn(t.buf, " \t\r");
        if (!*s)
            continue;
        if (isalpha((unsigned char)*s) && !ends_with_header_keyword(s))
            break;   /* first section keyword (a header line whose number is a
                      * word, "nan 0 0 xy xz yz", is refused as a header) */
        char line[256];
        snprintf(line, sizeof line, "%s", s);
        char *tok[8];
        int ntok = split_tokens(t.buf, tok, 8);
        if (ntok > 8) {   /* no header line has more than 7 words (tok[] holds 8) */
            rc = textfile_error(&t, e, "unrecognised header line '%s'", text_excerpt(line, ex));
            goto done;
        }
        long count;
        int k;
        if ((k = header_count(tok, ntok, "atoms", NULL, &count)) != 0) {
            if (k < 0 || natoms >= 0) {
                rc = k < 0 ? textfile_error(&t, e, "'atoms' needs a count >= 0, found '%s'",
                                            text_excerpt(tok[0], ex))
                           : textfile_error(&t, e, "a second 'atoms' line");
                goto done;
            }
            natoms = count;
            if ((rc = check_atom_count(&t, natoms, r, e)))
                goto done;
        } else if ((k = header_count(tok, ntok, "atom", "types", &count)) != 0) {
            if (k < 0 || ntypes >= 0) {
                rc = k < 0 ? textfile_error(&t, e, "'atom types' needs a count >= 0, found '%s'",
                                            text_excerpt(tok[0], ex))
                           : textfile_error(&t, e, "a second 'atom types' line");
                goto done;
            }
            ntypes = count;
        } else if (ntok == 6 && strcmp(tok[3], "xy") == 0 && strcmp(tok[4], "xz") == 0 &&
                   strcmp(tok[5], "yz") == 0) {
            /* a triclinic box (core/box.h); checked against the bounds
             * after the header (they may come later) */
            for (int q = 0; q < 3; q++)
                if (text_parse_real(tok[q], &tilt[q]) != 0) {
                    rc = textfile_error(&t, e, "xy xz yz: tilt factor %s must be a finite "
                                        "decimal number, found '%s'", tok[3 + q],
                                        text_excerpt(tok[q], ex));
                    goto done;
                }
            if (tilt_line) {
                rc = textfile_error(&t, e, "a second 'xy xz yz' line (the first is at line %d)",
                                    tilt_line);
                goto done;
            }
            tilt_line = t.line;
        } else if (ntok >= 4 && strcmp(tok[ntok - 1], "yz") == 0) {
            rc = textfile_error(&t, e, "unrecognised header line '%s' (a triclinic box is "
                                "'xy xz yz' after its three tilt factors)",
                                text_excerpt(line, ex));
            goto done;
        } else if (ntok == 4 && tok[2][0] == tok[3][0] && tok[2][0] >= 'x' && tok[2][0] <= 'z' &&
                   strcmp(tok[2] + 1, "lo") == 0 && strcmp(tok[3] + 1, "hi") == 0) {
            int d = tok[2][0] - 'x';
            double v[2];
            if (text_parse_real(tok[0], &v[0]) != 0 || text_parse_real(tok[1], &v[1]) != 0 ||
                !(v[1] > v[0])) {
                rc = textfile_error(&t, e, "%clo %chi: box bounds must be finite decimal numbers "
                                    "with lo < hi", tok[2][0], tok[2][0]);
                goto done;
            }
            if (have_box[d]) {
                rc = textfile_error(&t, e, "a second '%clo %chi' line", tok[2][0], tok[2][0]);
                goto done;
            }
            b->lo[d] = v[0];
            b->hi[d] = v[1];
            have_box[d] = 1;
        } else {
            int known = 0;
            for (size_t m = 0; m < sizeof molecular / sizeof molecular[0] && !known; m++) {
                k = header_count(tok, ntok, molecular[m][0], molecular[m][1], &count);
                if (k < 0) {
                    rc = textfile_error(&t, e, "'%s' needs a count >= 0, found '%s'",
                                        molecular[m][0], text_excerpt(tok[0], ex));
                    goto done;
                }
                known = k;
            }
            if (!known) {
                rc = textfile_error(&t, e, "unrecognised header line '%s'", text_excerpt(line, ex));
                goto done;
            }
        }
    }
    if (natoms < 0 || ntypes < 1) {
        rc = textfile_error(&t, e, "header must give 'N atoms' and 'M atom types'");
        goto done;
    }
    if (ntypes > PARTICLES_MAX_TYPES) {
        rc = textfile_error(&t, e, "at most %d atom types are supported, found %ld",
                            PARTICLES_MAX_TYPES, ntypes);
        goto done;
    }
    for (int d = 0; d < 3; d++)
        if (!have_box[d]) {
            rc = textfile_error(&t, e, "header lacks '%clo %chi'", "xyz"[d], "xyz"[d]);
            goto done;
        }
    if ((rc = accept_tilt(&t, tilt_line, "xy xz yz", tilt, r, b, e)))
        goto done;
    long natoms_read = 0;
    int atoms_line = 0, vel_line = 0;
    /* sections; t.buf holds the first keyword line */
    do {
        char *hash = strchr(t.buf, '#');
        char comment[128] = "";
        if (hash) {
            snprintf(comment, sizeof comment, "%s", hash + 1);
            *hash = '\0';
        }
        const char *s = t.buf + strspn(t.buf, " \t\r");
        if (!*s)
            continue;
        if (starts_with_word(s, "Masses")) {
            for (long k = 0; k < ntypes;) {
                if (textfile_next_line(&t) != 0) {
                    rc = textfile_error(&t, e, "Masses section ends early");
                    goto done;
                }
                char *h2 = strchr(t.buf, '#');
                char nm[32] = "";
                if (h2) {
                    sscanf(h2 + 1, "%31s", nm);
                    *h2 = '\0';
                }
                if (strlen(nm) >= sizeof names[0]) {
                    /* cut to fit, it would name another element (or none) */
                    rc = textfile_error(&t, e, "Masses: type name '%s' is longer than %zu "
                                        "characters", text_excerpt(nm, ex), sizeof names[0] - 1);
                    goto done;
                }
                double v[2];
                if (t.buf[strspn(t.buf, " \t\r")] == '\0')
                    continue;
                if (parse_doubles(t.buf, v, 2, NULL, 0) != 2 || !(v[0] >= 1 && v[0] <= ntypes) ||
                    v[0] != floor(v[0]) || !(v[1] > 0)) {
                    rc = textfile_error(&t, e, "Masses line must be 'type mass' with type 1..%ld "
                                        "and mass > 0", ntypes);
                    goto done;
                }
                int ty = (int)v[0] - 1;
                if (mass_line[ty]) {
                    rc = textfile_error(&t, e, "Masses: type %d is given twice (also at line %d)",
                                        ty + 1, mass_line[ty]);
                    goto done;
                }
                mass_line[ty] = t.line;
                masses[ty] = v[1];
                if (nm[0])
                    snprintf(names[ty], sizeof names[0], "%s", nm);
                k++;
            }
        } else if (starts_with_word(s, "Atoms")) {
            if (atoms_line) {
                rc = textfile_error(&t, e, "a second Atoms section (the first is at line %d)",
                                    atoms_line);
                goto done;
            }
            atoms_line = t.line;
            if (comment[0] && !strstr(comment, "atomic")) {
                rc = textfile_error(&t, e, "only atom_style atomic is supported (found '#%s')",
                                    text_excerpt(comment, ex));
                goto done;
            }
            /* type names: case elements, else Masses comments */
            for (long k = 0; k < ntypes; k++) {
                const char *nm = k < nelements ? elements[k] : names[k];
                if (!nm || !nm[0]) {
                    rc = err_set(e, ERR_INPUT,
                                 "%s: atom type %ld has no element name: list it in "
                                 "system.elements or comment the Masses line ('%ld 63.546 # Cu')",
                                 path, k + 1, k + 1);
                    goto done;
                }
                double m = masses[k] > 0 ? masses[k] : element_mass(nm);
                if (particles_type_index(p, nm, m) < 0) {
                    rc = err_set(e, ERR_INPUT, "%s: too many atom types", path);
                    goto done;
                }
            }
            while (natoms_read < natoms) {
                if (textfile_next_line(&t) != 0) {
                    rc = textfile_error(&t, e, "Atoms section has %ld of %ld atoms", natoms_read,
                                        natoms);
                    goto done;
                }
                char *h2 = strchr(t.buf, '#');
                if (h2)
                    *h2 = '\0';
                if (t.buf[strspn(t.buf, " \t\r")] == '\0')
                    continue;
                double v[8];
                char bad[48];
                int nv = parse_doubles(t.buf, v, 8, bad, sizeof bad);
                if (nv < 0) {
                    static const char *const field[] = {"id", "type", "x", "y", "z",
                                                        "ix", "iy", "iz"};
                    rc = textfile_error(&t, e, "Atoms line: field %d (%s) must be a finite "
                                        "decimal number, found '%s'", -nv, field[-nv - 1], bad);
                    goto done;
                }
                if (nv != 5 && nv != 8) {
                    rc = textfile_error(&t, e, "Atoms line must be 'id type x y z [ix iy iz]'");
                    goto done;
                }
                if (!(v[0] >= 1 && v[0] <= 9.0e15 && v[0] == floor(v[0]))) {
                    rc = textfile_error(&t, e, "Atoms line: id %.10g is not a positive integer",
                                        v[0]);
                    goto done;
                }
                if (!(v[1] >= 1 && v[1] <= (double)ntypes && v[1] == floor(v[1]))) {
                    rc = textfile_error(&t, e, "atom type %.10g out of range 1..%ld",
                                        v[1], ntypes);
                    goto done;
                }
                int image[3] = {0, 0, 0};
                if (nv == 8)
                    for (int d = 5; d < 8; d++) {
                        if (!(fabs(v[d]) < 1.0e9 && v[d] == floor(v[d]))) {
                            rc = textfile_error(&t, e, "Atoms line: image flag %.10g is not an "
                                                "integer", v[d]);
                            goto done;
                        }
                        image[d - 5] = (int)v[d];
                    }
                long type = (long)v[1];
                double x[3] = {v[2], v[3], v[4]};
                if ((rc = check_position(&t, r, b, (long)v[0], x, e)))
                    goto done;
                const char *nm = type - 1 < nelements ? elements[type - 1] : names[type - 1];
                int ti = particles_type_index(p, nm, 0);
                int idx = particles_add(p, x, NULL, ti, (int64_t)v[0]);
                if (idx < 0 || atom_lines_push(&al, t.line, e)) {
                    rc = err_nomem(e, "atoms");
                    goto done;
                }
                for (int d = 0; d < 3; d++)
                    p->image[3 * idx + d] = image[d];
                natoms_read++;
            }
            if ((rc = check_unique_ids(&t, p, base, &al, "Atoms", e)))
                goto done;
        } else if (starts_with_word(s, "Velocities")) {
            if (vel_line) {
                rc = textfile_error(&t, e, "a second Velocities section (the first is at line %d)",
                                    vel_line);
                goto done;
            }
            vel_line = t.line;
            /* map ids to indices: sorted (id, index) pairs, binary search
             * (ids are unique: checked at the end of Atoms) */
            long n_own = p->n_owned - base;
            int64_t (*pairs)[2] = malloc((size_t)(n_own ? n_own : 1) * sizeof *pairs);
            vline = calloc((size_t)(n_own ? n_own : 1), sizeof *vline);
            if (!pairs || !vline) {
                free(pairs);
                rc = err_nomem(e, "velocity lookup");
                goto done;
            }
            for (long i = 0; i < n_own; i++) {
                pairs[i][0] = p->id[base + i];
                pairs[i][1] = i;
            }
            qsort(pairs, (size_t)n_own, sizeof *pairs, cmp_id_pair);
            for (long k = 0; k < natoms;) {
                if (textfile_next_line(&t) != 0) {
                    free(pairs);
                    rc = textfile_error(&t, e, "Velocities section ends early");
                    goto done;
                }
                char *h2 = strchr(t.buf, '#');
                if (h2)
                    *h2 = '\0';
                if (t.buf[strspn(t.buf, " \t\r")] == '\0')
                    continue;
                double v[4];
                char bad[48];
                int nv = parse_doubles(t.buf, v, 4, bad, sizeof bad);
                if (nv < 0) {
                    free(pairs);
                    rc = textfile_error(&t, e, "Velocities line: field %d (%s) must be a finite "
                                        "decimal number, found '%s'", -nv,
                                        (const char *const[]){"id", "vx", "vy", "vz"}[-nv - 1], bad);
                    goto done;
                }
                if (nv != 4) {
                    free(pairs);
                    rc = textfile_error(&t, e, "Velocities line must be 'id vx vy vz'");
                    goto done;
                }
                if (!(v[0] >= 1 && v[0] <= 9.0e15 && v[0] == floor(v[0]))) {
                    free(pairs);
                    rc = textfile_error(&t, e, "Velocities line: id %.10g is not a positive "
                                        "integer", v[0]);
                    goto done;
                }
                int64_t key[2] = {(int64_t)v[0], 0};
                /* the lowest index with this id: compare ids only */
                long lo = 0, hi = n_own;
                while (lo < hi) {
                    long mid = lo + (hi - lo) / 2;
                    if (pairs[mid][0] < key[0])
                        lo = mid + 1;
                    else
                        hi = mid;
                }
                if (lo >= n_own || pairs[lo][0] != key[0]) {
                    free(pairs);
                    rc = textfile_error(&t, e, "velocity for unknown atom id %.0f", v[0]);
                    goto done;
                }
                long found = (long)pairs[lo][1];
                if (vline[found]) {
                    free(pairs);
                    rc = textfile_error(&t, e, "Velocities: atom id %.0f is given twice (also at "
                                        "line %d)", v[0], vline[found]);
                    goto done;
                }
                vline[found] = t.line;
                for (int d = 0; d < 3; d++)
                    p->v[3 * (base + found) + d] = v[1 + d];
                k++;
            }
            free(pairs);
        } else {
            rc = textfile_error(&t, e, "unsupported section '%s' (atomic style: Masses, Atoms, "
                                       "Velocities)",
                                text_excerpt(s, ex));
            goto done;
        }
    } while (textfile_next_line(&t) == 0);
    if (natoms_read != natoms) {
        rc = err_set(e, ERR_INPUT, "%s: header says %ld atoms, the Atoms section has %ld", path,
                     natoms, natoms_read);
        goto done;
    }
    rc = check_close_atoms(&t, p, base, b, r, &al, e);
done:
    free(al.line);
    free(vline);
    textfile_close(&t);
    return rc;
}

/* --- extended XYZ ---------------------------------------------------------- */

/* Value of key="..." or key=word in an extended XYZ comment line. */
static int xyz_attr(const char *line, const char *key, char *out, size_t len)
{
    size_t klen = strlen(key);
    const char *s = line;
    while ((s = strstr(s, key)) != NULL) {
        if ((s == line || isspace((unsigned char)s[-1])) && s[klen] == '=') {
            const char *v = s + klen + 1;
            if (*v == '"') {
                const char *end = strchr(v + 1, '"');
                if (!end)
                    return -1;
                snprintf(out, len, "%.*s", (int)(end - v - 1), v + 1);
            } else {
                snprintf(out, len, "%.*s", (int)strcspn(v, " \t"), v);
            }
            return 0;
        }
        s += klen;
    }
    return -1;
}

/* Velocity (Å/ps) of an atom line from ASE's momenta (amu Å / t_ASE,
 * t_ASE = Å sqrt(amu/eV) = sqrt(UNITS_MVV2E) ps) and its mass: the masses
 * column, else the element's standard mass. */
static int velocity_from_momenta(struct textfile *t, char **cols, int col_mom, int col_mass,
                                 const char *species, double v[3], struct err *e)
{
    char ex[TEXT_EXCERPT_SIZE];
    double m = element_mass(species);
    if (col_mass >= 0 && (text_parse_real(cols[col_mass], &m) != 0 || !(m > 0)))
        return textfile_error(t, e, "masses (column %d): '%s' is not a positive finite decimal "
                              "number", col_mass + 1, text_excerpt(cols[col_mass], ex));
    for (int d = 0; d < 3; d++) {
        double q;
        if (text_parse_real(cols[col_mom + d], &q) != 0)
            return textfile_error(t, e, "momenta (column %d): '%s' is not a finite decimal "
                                  "number", col_mom + d + 1, text_excerpt(cols[col_mom + d], ex));
        v[d] = q / (m * sqrt(UNITS_MVV2E));
    }
    return 0;
}

/* A count line: one integer >= 0 and nothing else. */
static int xyz_count_line(char *s, long *n)
{
    char *tok[2];
    return split_tokens(s, tok, 1) == 1 && text_parse_long(tok[0], n) == 0 && *n >= 0 ? 0 : -1;
}

int config_read_extxyz(const char *path, const struct config_rules *rules, struct particles *p,
                       struct box *b, int pbc[3], struct err *e)
{
    struct config_rules defrules = config_rules_default();
    const struct config_rules *r = rules ? rules : &defrules;
    struct textfile t;
    int rc = textfile_open(&t, path, e);
    if (rc)
        return rc;
    struct atom_lines al = {0};
    const int base = p->n_owned;
    char ex[TEXT_EXCERPT_SIZE];
    pbc[0] = pbc[1] = pbc[2] = 1;
    long n;
    if (textfile_next_line(&t) != 0 || xyz_count_line(t.buf, &n) != 0) {
        rc = textfile_error(&t, e, "first line must be the number of atoms (one integer >= 0)");
        goto done;
    }
    if ((rc = check_atom_count(&t, n, r, e)))
        goto done;
    if (textfile_next_line(&t) != 0) {
        rc = textfile_error(&t, e, "missing comment line");
        goto done;
    }
    char val[1024];
    if (xyz_attr(t.buf, "Lattice", val, sizeof val) != 0) {
        rc = textfile_error(&t, e, "comment line lacks Lattice=\"ax ay az bx by bz cx cy cz\"");
        goto done;
    }
    double L[9];
    if (parse_doubles(val, L, 9, NULL, 0) != 9) {
        rc = textfile_error(&t, e, "Lattice needs 9 finite decimal numbers");
        goto done;
    }
    /* LAMMPS' restricted triclinic cell (core/box.h): a along x, b in the
     * xy plane; a general cell would need the atoms rotated */
    for (int k = 1; k <= 5; k += (k == 2 ? 3 : 1))   /* ay az bz: k = 1 2 5 */
        if (L[k] != 0) {
            rc = textfile_error(&t, e, "Lattice vector %d has %c component %.10g: the cell "
                                "must be LAMMPS' restricted triclinic one (a = (lx 0 0), b = "
                                "(xy ly 0), c = (xz yz lz)); rotate the atoms to it",
                                k / 3 + 1, "xyz"[k % 3], L[k]);
            goto done;
        }
    double origin[3] = {0, 0, 0};
    if (xyz_attr(t.buf, "Origin", val, sizeof val) == 0 && parse_doubles(val, origin, 3, NULL, 0) != 3) {
        rc = textfile_error(&t, e, "Origin needs 3 finite decimal numbers");
        goto done;
    }
    for (int d = 0; d < 3; d++) {
        b->lo[d] = origin[d];
        b->hi[d] = origin[d] + L[4 * d];
        if (!(L[4 * d] > 0) || !isfinite(b->hi[d])) {
            rc = textfile_error(&t, e, "Lattice vector %d has non-positive length", d + 1);
            goto done;
        }
    }
    if (xyz_attr(t.buf, "pbc", val, sizeof val) == 0) {
        char a[3][8];
        if (sscanf(val, "%7s %7s %7s", a[0], a[1], a[2]) == 3)
            for (int d = 0; d < 3; d++)
                pbc[d] = a[d][0] == 'T' || a[d][0] == 't';
    }
    {
        double tilt[3] = {L[3], L[6], L[7]};   /* xy = b_x, xz = c_x, yz = c_y */
        b->tilt[0] = b->tilt[1] = b->tilt[2] = 0;
        if ((rc = accept_tilt(&t, t.line, "Lattice", tilt, r, b, e)))
            goto done;
    }
    /* Properties: find columns of species, pos, vel/velo, id */
    int col_species = 0, col_pos = 1, col_vel = -1, col_id = -1, col_mom = -1, col_mass = -1;
    int ncols = 4;
    if (xyz_attr(t.buf, "Properties", val, sizeof val) == 0) {
        int col = 0;
        col_species = col_pos = -1;
        char *save = NULL;
        char *tok = strtok_r(val, ":", &save);
        while (tok) {
            char *type = strtok_r(NULL, ":", &save);
            char *cnt = strtok_r(NULL, ":", &save);
            long c;
            if (!type || !cnt || text_parse_long(cnt, &c) != 0 || c < 1 || c > 64 ||
                strlen(type) != 1 || !strchr("SRIL", type[0])) {
                rc = textfile_error(&t, e, "malformed Properties at '%s' (name:type:count "
                                    "triples, type S, R, I or L, count 1..64)",
                                    text_excerpt(tok, ex));
                goto done;
            }
            /* the columns this reader uses must have the shape it reads */
            int *colp = NULL;
            const char *shape = NULL;
            if (strcmp(tok, "species") == 0) colp = &col_species, shape = "S:1";
            else if (strcmp(tok, "pos") == 0) colp = &col_pos, shape = "R:3";
            else if (strcmp(tok, "vel") == 0 || strcmp(tok, "velo") == 0 ||
                     strcmp(tok, "velocities") == 0) colp = &col_vel, shape = "R:3";
            else if (strcmp(tok, "id") == 0) colp = &col_id, shape = "I:1";
            else if (strcmp(tok, "momenta") == 0) colp = &col_mom, shape = "R:3";
            else if (strcmp(tok, "masses") == 0) colp = &col_mass, shape = "R:1";
            if (colp) {
                char got[16];
                snprintf(got, sizeof got, "%s:%ld", type, c);
                if (strcmp(got, shape) != 0) {
                    rc = textfile_error(&t, e, "Properties: %s must be %s:%s, found %s:%s",
                                        tok, tok, shape, tok, got);
                    goto done;
                }
                *colp = col;
            }
            col += (int)c;
            tok = strtok_r(NULL, ":", &save);
        }
        ncols = col;
        if (col_species < 0 || col_pos < 0) {
            rc = textfile_error(&t, e, "Properties must include species:S:1 and pos:R:3");
            goto done;
        }
        if (ncols > 64) {
            rc = textfile_error(&t, e, "Properties: at most 64 columns, found %d", ncols);
            goto done;
        }
    }
    int count_line = 1;
    for (long k = 0; k < n; k++) {
        if (textfile_next_line(&t) != 0) {
            rc = textfile_error(&t, e, "file has %ld of the %ld atoms of line %d", k, n,
                                count_line);
            goto done;
        }
        char *cols[64];
        int nc = split_tokens(t.buf, cols, 64);
        /* the species first: a second comment line, or a count line that
         * announces more atoms than there are, is read as an atom line */
        const char *sp = col_species < nc ? cols[col_species] : "";
        if (!element_known(sp)) {
            rc = textfile_error(&t, e, "species (column %d): '%s' is not a chemical element "
                                "symbol (line %d says %ld atoms follow the comment line)",
                                col_species + 1, text_excerpt(sp, ex), count_line, n);
            goto done;
        }
        if (nc != ncols) {
            rc = textfile_error(&t, e, "atom line has %s%d columns, Properties says %d",
                                nc > 64 ? "more than " : "", nc > 64 ? 64 : nc, ncols);
            goto done;
        }
        double x[3], v[3] = {0, 0, 0};
        for (int d = 0; d < 3; d++) {
            if (text_parse_real(cols[col_pos + d], &x[d]) != 0) {
                rc = textfile_error(&t, e, "pos (column %d): '%s' is not a finite decimal "
                                    "number", col_pos + d + 1, text_excerpt(cols[col_pos + d], ex));
                goto done;
            }
            if (col_vel >= 0 && text_parse_real(cols[col_vel + d], &v[d]) != 0) {
                rc = textfile_error(&t, e, "velocities (column %d): '%s' is not a finite "
                                    "decimal number", col_vel + d + 1,
                                    text_excerpt(cols[col_vel + d], ex));
                goto done;
            }
        }
        if (col_vel < 0 && col_mom >= 0 &&
            (rc = velocity_from_momenta(&t, cols, col_mom, col_mass, sp, v, e)))
            goto done;
        int ti = particles_type_index(p, sp, element_mass(sp));
        if (ti < 0) {
            rc = textfile_error(&t, e, "too many species (at most %d)", PARTICLES_MAX_TYPES);
            goto done;
        }
        long idv = k + 1;
        if (col_id >= 0 && (text_parse_long(cols[col_id], &idv) != 0 || idv < 1)) {
            rc = textfile_error(&t, e, "id (column %d): '%s' is not a positive integer",
                                col_id + 1, text_excerpt(cols[col_id], ex));
            goto done;
        }
        if ((rc = check_position(&t, r, b, idv, x, e)))
            goto done;
        if (particles_add(p, x, v, ti, (int64_t)idv) < 0 || atom_lines_push(&al, t.line, e)) {
            rc = err_nomem(e, "atoms");
            goto done;
        }
    }
    /* after the atoms: nothing, or the count line of a next frame.  Any
     * other line means the count line and the atom lines disagree. */
    if (textfile_next_content_line(&t) == 0) {
        long n2;
        char first[256];
        snprintf(first, sizeof first, "%s", t.buf);
        if (xyz_count_line(t.buf, &n2) != 0) {
            rc = textfile_error(&t, e, "'%s' follows the %ld atoms that line %d announces; "
                                "expected the end of the file or the count line of a next frame",
                                text_excerpt(first + strspn(first, " \t"), ex), n, count_line);
            goto done;
        }
    }
    if ((rc = check_unique_ids(&t, p, base, &al, "id", e)))
        goto done;
    rc = check_close_atoms(&t, p, base, b, r, &al, e);
done:
    free(al.line);
    textfile_close(&t);
    return rc;
}
