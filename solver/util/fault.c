/* fault: the process-wide allocation and write fault counters (fault.h). */
#include "util/fault.h"

#include <errno.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

struct fault_counter {
    int on;              /* installed */
    long at;             /* fail call number `at` (1-based); 0: count only */
    int persist;         /* and every call after it */
    atomic_long calls;   /* calls seen */
    atomic_long failed;  /* calls failed */
};

/* the exception to "no global mutable state" documented in fault.h */
static struct fault_counter alloc_counter, write_counter;

static int counter_hit(struct fault_counter *c)
{
    if (!c->on)
        return 0;
    long n = atomic_fetch_add(&c->calls, 1) + 1;
    int hit = c->at > 0 && (n == c->at || (c->persist && n > c->at));
    if (hit)
        atomic_fetch_add(&c->failed, 1);
    return hit;
}

static int parse(const char *name, const char *spec, struct fault_counter *c, struct err *e)
{
    c->on = 0;
    if (!spec || !spec[0])
        return 0;
    char *end;
    errno = 0;
    long n = strtol(spec, &end, 10);
    if (end == spec || errno || n < 0 || (*end && strcmp(end, "+") != 0))
        return err_set(e, ERR_INPUT,
                       "%s=%s: expected N (fail the Nth call), N+ (fail it and every later one) "
                       "or 0 (count only)",
                       name, spec);
    c->at = n;
    c->persist = *end == '+';
    atomic_store(&c->calls, 0);
    atomic_store(&c->failed, 0);
    c->on = 1;
    return 0;
}

int fault_install(const char *alloc_spec, const char *write_spec, struct err *e)
{
    int rc = parse("CASCADE_FAULT_ALLOC", alloc_spec, &alloc_counter, e);
    return rc ? rc : parse("CASCADE_FAULT_WRITE", write_spec, &write_counter, e);
}

int fault_installed(void)
{
    return alloc_counter.on || write_counter.on;
}

int fault_alloc_fails(void)
{
    return counter_hit(&alloc_counter);
}

int fault_write(int err)
{
    if (!counter_hit(&write_counter))
        return 0;
    errno = err;
    return -1;
}

static void report_one(FILE *f, const char *prog, const char *what, struct fault_counter *c)
{
    if (c->on)
        fprintf(f, "%s: fault injection: %s: %ld calls, failed %ld\n", prog, what,
                atomic_load(&c->calls), atomic_load(&c->failed));
}

void fault_report(FILE *f, const char *prog)
{
    report_one(f, prog, "alloc", &alloc_counter);
    report_one(f, prog, "write", &write_counter);
}
