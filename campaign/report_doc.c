/* report_doc: Markdown and self-contained HTML output of a report. */
#include "report_doc.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "util/mem.h"
#include "util/wfile.h"

enum block_kind { B_HEADING, B_PARA, B_TABLE, B_FIGURE };

struct block {
    enum block_kind kind;
    int level;             /* heading */
    char *text;            /* heading, paragraph, figure caption */
    int ncols, nrows;      /* table */
    char **cells;          /* (nrows + 1) * ncols, header first */
    char *dir, *file;      /* figure */
};

struct rdoc {
    char *title;
    int n, cap;
    struct block *b;
    int oom;   /* an allocation failed: the document is incomplete, writing it fails */
};

struct rdoc *rdoc_create(const char *title)
{
    struct rdoc *d = mem_calloc(1, sizeof *d);
    if (d && !(d->title = mem_strdup(title ? title : "")))
        d->oom = 1;
    return d;
}

void rdoc_destroy(struct rdoc **pd)
{
    struct rdoc *d = pd ? *pd : NULL;
    if (!d)
        return;
    for (int i = 0; i < d->n; i++) {
        struct block *b = &d->b[i];
        free(b->text);
        free(b->dir);
        free(b->file);
        if (b->cells)
            for (int k = 0; k < (b->nrows + 1) * b->ncols; k++)
                free(b->cells[k]);
        free(b->cells);
    }
    free(d->b);
    free(d->title);
    free(d);
    *pd = NULL;
}

void rdoc_mark_incomplete(struct rdoc *d)
{
    if (d)
        d->oom = 1;
}

static struct block *push(struct rdoc *d, enum block_kind kind)
{
    if (d->n == d->cap) {
        int cap = d->cap ? 2 * d->cap : 32;
        struct block *nb = mem_realloc(d->b, (size_t)cap * sizeof *nb);
        if (!nb) {
            d->oom = 1;
            return NULL;
        }
        d->b = nb;
        d->cap = cap;
    }
    struct block *b = &d->b[d->n++];
    memset(b, 0, sizeof *b);
    b->kind = kind;
    return b;
}

void rdoc_heading(struct rdoc *d, int level, const char *text)
{
    struct block *b = push(d, B_HEADING);
    if (b) {
        b->level = level;
        d->oom |= !(b->text = mem_strdup(text));
    }
}

void rdoc_para(struct rdoc *d, const char *fmt, ...)
{
    struct block *b = push(d, B_PARA);
    if (!b)
        return;
    va_list ap;
    va_start(ap, fmt);
    char buf[8192];
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    d->oom |= !(b->text = mem_strdup(buf));
}

void rdoc_table(struct rdoc *d, int ncols, const char *const *header, int nrows,
                const char *const *cells)
{
    struct block *b = push(d, B_TABLE);
    if (!b)
        return;
    b->ncols = ncols;
    b->nrows = nrows;
    b->cells = mem_calloc((size_t)(nrows + 1) * ncols, sizeof *b->cells);
    if (!b->cells) {
        d->oom = 1;
        return;
    }
    for (int c = 0; c < ncols; c++)
        d->oom |= !(b->cells[c] = mem_strdup(header[c] ? header[c] : ""));
    for (int k = 0; k < nrows * ncols; k++)
        d->oom |= !(b->cells[ncols + k] = mem_strdup(cells[k] ? cells[k] : ""));
}

void rdoc_figure(struct rdoc *d, const char *dir, const char *svg_name, const char *caption)
{
    struct block *b = push(d, B_FIGURE);
    if (b) {
        b->dir = mem_strdup(dir);
        b->file = mem_strdup(svg_name);
        b->text = mem_strdup(caption ? caption : "");
        d->oom |= !b->dir || !b->file || !b->text;
    }
}

/* Text of any block as literal Markdown: swept string parameters reach
 * headings, cells and captions, and Markdown passes raw HTML (<script>) and
 * entities through, starts code spans at backticks, links at brackets and
 * ends a table row or a heading at a newline.  So '<', '>' and '&' become
 * entities, the other active characters get a backslash (a backslash too,
 * so a value ending in one cannot escape what follows), and control
 * characters (newlines) become spaces -- as the HTML page shows them. */
static void md_text(FILE *f, const char *s)
{
    for (; s && *s; s++) {
        unsigned char c = (unsigned char)*s;
        switch (c) {
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '&': fputs("&amp;", f); break;
        case '|':
        case '`':
        case '\\':
        case '[':
        case ']':
            fputc('\\', f);
            fputc(c, f);
            break;
        default: fputc(c < 0x20 || c == 0x7f ? ' ' : c, f);
        }
    }
}

int rdoc_write_markdown(const struct rdoc *d, const char *path, struct err *e)
{
    if (!d || d->oom)
        return err_set(e, ERR_RUNTIME, "cannot write %s: out of memory (report)", path);
    struct wfile w;
    int rc = wfile_open(&w, path, e);
    if (rc)
        return rc;
    FILE *f = w.f;
    fputs("# ", f);
    md_text(f, d->title);
    fputs("\n\n", f);
    for (int i = 0; i < d->n; i++) {
        const struct block *b = &d->b[i];
        switch (b->kind) {
        case B_HEADING:
            fprintf(f, "%.*s ", b->level + 1, "######");
            md_text(f, b->text);
            fputs("\n\n", f);
            break;
        case B_PARA:
            md_text(f, b->text);
            fputs("\n\n", f);
            break;
        case B_TABLE:
            for (int r = 0; r <= b->nrows; r++) {
                fputc('|', f);
                for (int c = 0; c < b->ncols; c++) {
                    fputc(' ', f);
                    md_text(f, b->cells[r * b->ncols + c]);
                    fputs(" |", f);
                }
                fputc('\n', f);
                if (r == 0) {
                    fputc('|', f);
                    for (int c = 0; c < b->ncols; c++)
                        fputs("---|", f);
                    fputc('\n', f);
                }
            }
            fputc('\n', f);
            break;
        case B_FIGURE:
            /* the file name is the report's own (file_safe), not escaped */
            fputs("![", f);
            md_text(f, b->text);
            fprintf(f, "](%s)\n\n*", b->file);
            md_text(f, b->text);
            fputs("*\n\n", f);
            break;
        }
    }
    return wfile_commit(&w, e);
}

static void html_text(FILE *f, const char *s)
{
    for (; s && *s; s++) {
        switch (*s) {
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '&': fputs("&amp;", f); break;
        case '"': fputs("&quot;", f); break;
        default: fputc(*s, f);
        }
    }
}

/* Whether a cell reads as a number (right-aligned in HTML): "1.5e-3",
 * "-2", "+0", "± 0.03 K", "12 %", "—". */
static int is_number(const char *s)
{
    if (strncmp(s, "± ", strlen("± ")) == 0)
        s += strlen("± ");
    if (strcmp(s, "—") == 0 || strcmp(s, "-") == 0)
        return 1;
    char *end;
    strtod(s, &end);
    if (end == s)
        return 0;
    while (*end == ' ')
        end++;
    /* a number may be followed by a short unit */
    return strlen(end) <= 8 && !strchr(end, ' ');
}

/* Inline the SVG, dropping its XML prolog (not allowed inside HTML). */
static int inline_svg(FILE *out, const char *dir, const char *file)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    FILE *in = fopen(path, "r");
    if (!in)
        return -1;
    char line[8192];
    int started = 0;
    while (fgets(line, sizeof line, in)) {
        if (!started) {
            char *svg = strstr(line, "<svg");
            if (!svg)
                continue;
            started = 1;
            fputs(svg, out);
            continue;
        }
        fputs(line, out);
    }
    fclose(in);
    return started ? 0 : -1;
}

int rdoc_write_html(const struct rdoc *d, const char *path, struct err *e)
{
    if (!d || d->oom)
        return err_set(e, ERR_RUNTIME, "cannot write %s: out of memory (report)", path);
    struct wfile w;
    int rc = wfile_open(&w, path, e);
    if (rc)
        return rc;
    FILE *f = w.f;
    fputs("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>", f);
    html_text(f, d->title);
    fputs("</title>\n<style>\n"
          "body{font-family:sans-serif;max-width:60em;margin:2em auto;padding:0 1em;color:#222}\n"
          "table{border-collapse:collapse;margin:1em 0}\n"
          "th,td{border:1px solid #bbb;padding:.25em .6em;text-align:left;vertical-align:top}\n"
          "th{background:#eee}\ntd.n{text-align:right;white-space:nowrap}\n"
          "figure{margin:1.5em 0}figcaption{font-style:italic;color:#555}\n"
          ".flag{color:#b00;font-weight:bold}\n"
          "</style>\n</head>\n<body>\n<h1>",
          f);
    html_text(f, d->title);
    fputs("</h1>\n", f);
    for (int i = 0; i < d->n; i++) {
        const struct block *b = &d->b[i];
        switch (b->kind) {
        case B_HEADING:
            fprintf(f, "<h%d>", b->level + 1);
            html_text(f, b->text);
            fprintf(f, "</h%d>\n", b->level + 1);
            break;
        case B_PARA:
            fputs("<p>", f);
            html_text(f, b->text);
            fputs("</p>\n", f);
            break;
        case B_TABLE:
            fputs("<table>\n", f);
            for (int r = 0; r <= b->nrows; r++) {
                fputs("<tr>", f);
                for (int c = 0; c < b->ncols; c++) {
                    fputs(r ? (is_number(b->cells[r * b->ncols + c]) ? "<td class=\"n\">" : "<td>")
                            : "<th>",
                          f);
                    html_text(f, b->cells[r * b->ncols + c]);
                    fputs(r ? "</td>" : "</th>", f);
                }
                fputs("</tr>\n", f);
            }
            fputs("</table>\n", f);
            break;
        case B_FIGURE:
            fputs("<figure>\n", f);
            if (inline_svg(f, b->dir, b->file) != 0) {
                fputs("<p class=\"flag\">figure missing: ", f);
                html_text(f, b->file);
                fputs("</p>", f);
            }
            fputs("<figcaption>", f);
            html_text(f, b->text);
            fputs("</figcaption>\n</figure>\n", f);
            break;
        }
    }
    fputs("</body>\n</html>\n", f);
    return wfile_commit(&w, e);
}
