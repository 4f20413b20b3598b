/* config_read: LAMMPS data and extended XYZ readers. */
#include "input/config_read.h"

#include <ctype.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/textfile.h"
#include "core/elements.h"

static int starts_with_word(const char *line, const char *word)
{
    const char *s = line + strspn(line, " \t");
    size_t n = strlen(word);
    return strncmp(s, word, n) == 0 && (s[n] == '\0' || isspace((unsigned char)s[n]) || s[n] == '#');
}

static int cmp_id_pair(const void *a, const void *b)
{
    int64_t x = ((const int64_t *)a)[0], y = ((const int64_t *)b)[0];
    return (x > y) - (x < y);
}

/* Up to n whitespace-separated numbers of s, each parsed strictly
 * (text_parse_real).  Returns how many were read, or -(k+1) when token k is
 * not a finite decimal number (its text in *bad). */
static int parse_doubles(const char *s, double *out, int n, char *bad, size_t badlen)
{
    int k = 0;
    while (k < n) {
        s += strspn(s, " \t\r");
        if (!*s)
            break;
        size_t len = strcspn(s, " \t\r");
        char tok[128];
        snprintf(tok, sizeof tok, "%.*s", (int)(len < sizeof tok ? len : sizeof tok - 1), s);
        if (len >= sizeof tok || text_parse_real(tok, &out[k]) != 0) {
            if (bad)
                snprintf(bad, badlen, "%.40s", tok);
            return -(k + 1);
        }
        s += len;
        k++;
    }
    return k;
}

int config_read_lammps_data(const char *path, const char *const *elements, int nelements,
                            struct particles *p, struct box *b, struct err *e)
{
    struct textfile t;
    int rc = textfile_open(&t, path, e);
    if (rc)
        return rc;
    long natoms = -1, ntypes = -1;
    int have_box[3] = {0, 0, 0};
    double masses[PARTICLES_MAX_TYPES] = {0};
    char names[PARTICLES_MAX_TYPES][16] = {{0}};
    textfile_next_line(&t);   /* title */
    /* header */
    while (textfile_next_line(&t) == 0) {
        char *hash = strchr(t.buf, '#');
        if (hash)
            *hash = '\0';
        const char *s = t.buf + strspn(t.buf, " \t");
        if (!*s)
            continue;
        double v[3];
        if (strstr(s, "xy xz yz")) {
            rc = textfile_error(&t, e, "triclinic boxes are not supported");
            goto done;
        }
        if (strstr(s, "atom types")) {
            ntypes = strtol(s, NULL, 10);
        } else if (strstr(s, "atoms")) {
            natoms = strtol(s, NULL, 10);
        } else if (strstr(s, "xlo xhi") || strstr(s, "ylo yhi") || strstr(s, "zlo zhi")) {
            int d = strstr(s, "xlo") ? 0 : strstr(s, "ylo") ? 1 : 2;
            if (parse_doubles(s, v, 2, NULL, 0) != 2 || !(v[1] > v[0])) {
                rc = textfile_error(&t, e, "box bounds need lo < hi");
                goto done;
            }
            b->lo[d] = v[0];
            b->hi[d] = v[1];
            have_box[d] = 1;
        } else if (isalpha((unsigned char)*s)) {
            break;   /* first section keyword */
        } else if (strstr(s, "bonds") || strstr(s, "angles") || strstr(s, "types") ||
                   strstr(s, "dihedrals") || strstr(s, "impropers")) {
            continue;   /* molecular counts: ignored, atomic style has none */
        } else {
            rc = textfile_error(&t, e, "unrecognised header line '%s'", s);
            goto done;
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
    long natoms_read = 0;
    int have_vel = 0;
    /* sections; t.buf holds the first keyword line */
    do {
        char *hash = strchr(t.buf, '#');
        char comment[128] = "";
        if (hash) {
            snprintf(comment, sizeof comment, "%s", hash + 1);
            *hash = '\0';
        }
        const char *s = t.buf + strspn(t.buf, " \t");
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
                double v[2];
                if (t.buf[strspn(t.buf, " \t")] == '\0')
                    continue;
                if (parse_doubles(t.buf, v, 2, NULL, 0) != 2 || v[0] < 1 || v[0] > ntypes || !(v[1] > 0)) {
                    rc = textfile_error(&t, e, "Masses line must be 'type mass' with mass > 0");
                    goto done;
                }
                masses[(int)v[0] - 1] = v[1];
                if (nm[0])
                    snprintf(names[(int)v[0] - 1], sizeof names[0], "%s", nm);
                k++;
            }
        } else if (starts_with_word(s, "Atoms")) {
            if (comment[0] && !strstr(comment, "atomic")) {
                rc = textfile_error(&t, e, "only atom_style atomic is supported (found '#%s')",
                                    comment);
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
                if (t.buf[strspn(t.buf, " \t")] == '\0')
                    continue;
                double v[9];
                char bad[48];
                int nv = parse_doubles(t.buf, v, 9, bad, sizeof bad);
                if (nv < 0) {
                    static const char *const field[] = {"id", "type", "x", "y", "z",
                                                        "ix", "iy", "iz", "extra"};
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
                if (nv == 8)
                    for (int d = 5; d < 8; d++)
                        if (!(fabs(v[d]) < 1.0e9 && v[d] == floor(v[d]))) {
                            rc = textfile_error(&t, e, "Atoms line: image flag %.10g is not an "
                                                "integer", v[d]);
                            goto done;
                        }
                long type = (long)v[1];
                double x[3] = {v[2], v[3], v[4]};
                const char *nm = type - 1 < nelements ? elements[type - 1] : names[type - 1];
                int ti = particles_type_index(p, nm, 0);
                int idx = particles_add(p, x, NULL, ti, (int64_t)v[0]);
                if (idx < 0) {
                    rc = err_nomem(e, "atoms");
                    goto done;
                }
                if (nv == 8)
                    for (int d = 0; d < 3; d++)
                        p->image[3 * idx + d] = (int)v[5 + d];
                natoms_read++;
            }
        } else if (starts_with_word(s, "Velocities")) {
            have_vel = 1;
            /* map ids to indices: sorted (id, index) pairs, binary search */
            long n_own = p->n_owned;
            int64_t (*pairs)[2] = malloc((size_t)(n_own ? n_own : 1) * sizeof *pairs);
            if (!pairs) {
                rc = err_nomem(e, "velocity lookup");
                goto done;
            }
            for (long i = 0; i < n_own; i++) {
                pairs[i][0] = p->id[i];
                pairs[i][1] = i;
            }
            qsort(pairs, (size_t)n_own, sizeof *pairs, cmp_id_pair);
            for (long k = 0; k < natoms;) {
                if (textfile_next_line(&t) != 0) {
                    free(pairs);
                    rc = textfile_error(&t, e, "Velocities section ends early");
                    goto done;
                }
                if (t.buf[strspn(t.buf, " \t")] == '\0')
                    continue;
                double v[5];
                char bad[48];
                int nv = parse_doubles(t.buf, v, 5, bad, sizeof bad);
                if (nv < 0) {
                    free(pairs);
                    rc = textfile_error(&t, e, "Velocities line: field %d (%s) must be a finite "
                                        "decimal number, found '%s'", -nv,
                                        (const char *const[]){"id", "vx", "vy", "vz", "extra"}[-nv - 1], bad);
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
                int64_t(*hit)[2] = bsearch(key, pairs, (size_t)n_own, sizeof *pairs, cmp_id_pair);
                if (!hit) {
                    free(pairs);
                    rc = textfile_error(&t, e, "velocity for unknown atom id %.0f", v[0]);
                    goto done;
                }
                int found = (int)(*hit)[1];
                for (int d = 0; d < 3; d++)
                    p->v[3 * found + d] = v[1 + d];
                k++;
            }
            free(pairs);
        } else {
            rc = textfile_error(&t, e, "unsupported section '%s' (atomic style: Masses, Atoms, "
                                       "Velocities)",
                                s);
            goto done;
        }
    } while (textfile_next_line(&t) == 0);
    if (natoms_read != natoms) {
        rc = err_set(e, ERR_INPUT, "%s: header says %ld atoms, the Atoms section has %ld", path,
                     natoms, natoms_read);
        goto done;
    }
    (void)have_vel;
done:
    textfile_close(&t);
    return rc;
}

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

int config_read_extxyz(const char *path, struct particles *p, struct box *b, int pbc[3],
                       struct err *e)
{
    struct textfile t;
    int rc = textfile_open(&t, path, e);
    if (rc)
        return rc;
    pbc[0] = pbc[1] = pbc[2] = 1;
    long n;
    if (textfile_next_line(&t) != 0 || sscanf(t.buf, "%ld", &n) != 1 || n < 0) {
        rc = textfile_error(&t, e, "first line must be the number of atoms");
        goto done;
    }
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
        rc = textfile_error(&t, e, "Lattice needs 9 numbers");
        goto done;
    }
    if (L[1] != 0 || L[2] != 0 || L[3] != 0 || L[5] != 0 || L[6] != 0 || L[7] != 0) {
        rc = textfile_error(&t, e, "only orthogonal lattices are supported");
        goto done;
    }
    double origin[3] = {0, 0, 0};
    if (xyz_attr(t.buf, "Origin", val, sizeof val) == 0 && parse_doubles(val, origin, 3, NULL, 0) != 3) {
        rc = textfile_error(&t, e, "Origin needs 3 numbers");
        goto done;
    }
    for (int d = 0; d < 3; d++) {
        b->lo[d] = origin[d];
        b->hi[d] = origin[d] + L[4 * d];
        if (!(L[4 * d] > 0)) {
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
    /* Properties: find columns of species, pos, vel/velo, id */
    int col_species = 0, col_pos = 1, col_vel = -1, col_id = -1, ncols = 4;
    if (xyz_attr(t.buf, "Properties", val, sizeof val) == 0) {
        int col = 0;
        col_species = col_pos = -1;
        char *save = NULL;
        char *tok = strtok_r(val, ":", &save);
        while (tok) {
            char *type = strtok_r(NULL, ":", &save);
            char *cnt = strtok_r(NULL, ":", &save);
            if (!type || !cnt) {
                rc = textfile_error(&t, e, "malformed Properties (name:type:count triples)");
                goto done;
            }
            int c = atoi(cnt), need = 0;
            if (strcmp(tok, "species") == 0) col_species = col, need = 1;
            else if (strcmp(tok, "pos") == 0) col_pos = col, need = 3;
            else if (strcmp(tok, "vel") == 0 || strcmp(tok, "velo") == 0 || strcmp(tok, "velocities") == 0) col_vel = col, need = 3;
            else if (strcmp(tok, "id") == 0) col_id = col, need = 1;
            /* the columns read below must lie inside the atom lines */
            if (need ? c != need : c < 1 || c > 64) {
                rc = need ? textfile_error(&t, e, "Properties: %s needs %d columns, found '%s'",
                                           tok, need, cnt)
                          : textfile_error(&t, e, "Properties: %s has '%s' columns (1 to 64)",
                                           tok, cnt);
                goto done;
            }
            col += c;
            tok = strtok_r(NULL, ":", &save);
        }
        ncols = col;
        if (col_species < 0 || col_pos < 0) {
            rc = textfile_error(&t, e, "Properties must include species:S:1 and pos:R:3");
            goto done;
        }
    }
    for (long k = 0; k < n; k++) {
        if (textfile_next_line(&t) != 0) {
            rc = textfile_error(&t, e, "file has %ld of %ld atoms", k, n);
            goto done;
        }
        char *cols[64];
        int nc = 0;
        char *save = NULL;
        for (char *tok = strtok_r(t.buf, " \t", &save); tok && nc < 64;
             tok = strtok_r(NULL, " \t", &save))
            cols[nc++] = tok;
        if (nc < ncols) {
            rc = textfile_error(&t, e, "atom line has %d columns, Properties needs %d", nc, ncols);
            goto done;
        }
        double x[3], v[3] = {0, 0, 0};
        for (int d = 0; d < 3; d++) {
            if (text_parse_real(cols[col_pos + d], &x[d]) != 0) {
                rc = textfile_error(&t, e, "pos (column %d): '%.40s' is not a finite decimal "
                                    "number", col_pos + d + 1, cols[col_pos + d]);
                goto done;
            }
            if (col_vel >= 0 && text_parse_real(cols[col_vel + d], &v[d]) != 0) {
                rc = textfile_error(&t, e, "velocities (column %d): '%.40s' is not a finite "
                                    "decimal number", col_vel + d + 1, cols[col_vel + d]);
                goto done;
            }
        }
        const char *sp = cols[col_species];
        int ti = particles_type_index(p, sp, element_mass(sp));
        if (ti < 0) {
            rc = textfile_error(&t, e, "too many species");
            goto done;
        }
        long idv = k + 1;
        if (col_id >= 0 && (text_parse_long(cols[col_id], &idv) != 0 || idv < 1)) {
            rc = textfile_error(&t, e, "id (column %d): '%.40s' is not a positive integer",
                                col_id + 1, cols[col_id]);
            goto done;
        }
        int64_t id = (int64_t)idv;
        if (particles_add(p, x, v, ti, id) < 0) {
            rc = err_nomem(e, "atoms");
            goto done;
        }
    }
done:
    textfile_close(&t);
    return rc;
}
