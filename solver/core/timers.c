/* timers: monotonic clock and the timer name tables. */
#include "core/timers.h"

#include <time.h>

const char *const timer_names[TIMER_COUNT] = {
    "total", "  setup", "  loop", "    neighbor", "    comm", "    force", "    integrate",
    "    mpm p2g", "    mpm grid", "    mpm g2p", "    dpd sweep", "    coupling",
    "    analysis", "    output",
    "    checkpoint"};
const char *const timer_keys[TIMER_COUNT] = {
    "total", "setup", "loop", "neighbor", "comm", "force", "integrate",
    "mpm_p2g", "mpm_grid", "mpm_g2p", "dpd_sweep", "coupling", "analysis", "output",
    "checkpoint"};

double timers_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double timers_cpu_now(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts) != 0)
        return 0;
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}
