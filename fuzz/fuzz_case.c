/* fuzz_case: case files as `cascade-solver resolve CASE.yaml` reads them
 * (YAML from a file, validated and resolved without opening the files it
 * names), and as `resolve --batch` reads them (one JSON text).  A case that
 * resolves must resolve again, from its canonical JSON, to the same key: the
 * resolved document is what the campaign runner stores and re-submits. */
#include "fuzz/common.h"
#include "fuzz/fuzz.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "input/case.h"
#include "util/canon.h"

/* Resolve (shallow); on success *key receives the job key and the return
 * value is the canonical text (malloc'ed), else NULL. */
static char *resolve(struct case_doc *cd, char key[CANON_KEY_LEN + 1])
{
    struct err e = {0};
    struct case_resolved cr;
    int rc = case_resolve(cd, 1, 1, NULL, &cr, &e);
    fuzz_check_error(rc, e.msg);
    if (rc)
        return NULL;
    case_resolved_free(&cr);
    canon_key(cd->doc, key);
    char *text = canon_json(cd->doc);
    if (!text)
        abort();
    return text;
}

static void again(const char *text, const char *key)
{
    struct err e = {0};
    struct case_doc cd;
    int rc = case_load_json(&cd, text, "<resolved>", &e);
    char key2[CANON_KEY_LEN + 1];
    char *text2 = rc ? NULL : resolve(&cd, key2);
    if (!text2 || strcmp(key, key2) != 0) {
        fprintf(stderr, "fuzz_case: the resolved case does not resolve to itself\n%s\n%s\n%s\n",
                text, text2 ? text2 : "(error)", text2 ? "" : e.msg);
        abort();
    }
    free(text2);
    case_doc_free(&cd);
}

int fuzz_case_one(const uint8_t *data, size_t size)
{
    char dir[FUZZ_PATH_MAX], path[FUZZ_PATH_MAX + 64];
    char key[CANON_KEY_LEN + 1];
    fuzz_dir_create(dir, sizeof dir);
    fuzz_write(dir, "case.yaml", data, size, path, sizeof path);
    struct err e = {0};
    struct case_doc cd;
    int rc = case_load_file(&cd, path, &e);
    fuzz_check_error(rc, e.msg);
    if (!rc) {
        char *text = resolve(&cd, key);
        if (text)
            again(text, key);
        free(text);
    }
    case_doc_free(&cd);
    fuzz_dir_remove(dir);

    /* resolve --batch: the same bytes as one JSON case */
    char *json = fuzz_text(data, size);
    memset(&e, 0, sizeof e);
    rc = case_load_json(&cd, json, "<stdin line 1>", &e);
    fuzz_check_error(rc, e.msg);
    if (!rc) {
        char *text = resolve(&cd, key);
        free(text);
    }
    case_doc_free(&cd);
    free(json);
    return 0;
}

FUZZ_ENTRY(case)
