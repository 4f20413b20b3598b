/* sysinfo: clocks, host name, runner identity and liveness. */
#include "sysinfo.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>

double sys_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double sys_mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void sys_iso_time(double t, char *buf, size_t len)
{
    time_t s = (time_t)t;
    int ms = (int)((t - (double)s) * 1000.0);
    if (ms < 0)
        ms = 0;
    if (ms > 999)
        ms = 999;
    struct tm tm;
    gmtime_r(&s, &tm);
    char base[32];
    strftime(base, sizeof base, "%Y-%m-%dT%H:%M:%S", &tm);
    snprintf(buf, len, "%s.%03dZ", base, ms);
}

void sys_hostname(char *buf, size_t len)
{
    if (gethostname(buf, len) != 0)
        snprintf(buf, len, "localhost");
    buf[len - 1] = '\0';
}

unsigned long long sys_proc_start(pid_t pid)
{
    char path[64], line[1024];
    snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
    FILE *f = fopen(path, "r");
    if (!f)
        return 0;
    size_t n = fread(line, 1, sizeof line - 1, f);
    fclose(f);
    line[n] = '\0';
    /* the command name is in parentheses and may hold spaces: skip past ')' */
    char *p = strrchr(line, ')');
    if (!p)
        return 0;
    p++;
    /* fields after ')' start at field 3 (state); starttime is field 22 */
    for (int field = 3; field < 22 && p; field++) {
        p = strchr(p + 1, ' ');
    }
    return p ? strtoull(p + 1, NULL, 10) : 0;
}

void sys_runner_id(char *buf, size_t len)
{
    char host[256];
    sys_hostname(host, sizeof host);
    pid_t pid = getpid();
    snprintf(buf, len, "%s:%d:%llu", host, (int)pid, sys_proc_start(pid));
}

int sys_runner_alive(const char *id)
{
    char host[256];
    sys_hostname(host, sizeof host);
    const char *c1 = strrchr(id, ':');
    if (!c1 || c1 == id)
        return -1;
    const char *c2 = c1 - 1;
    while (c2 > id && *c2 != ':')
        c2--;
    if (*c2 != ':')
        return -1;
    size_t hlen = (size_t)(c2 - id);
    if (hlen != strlen(host) || strncmp(id, host, hlen) != 0)
        return -1;
    pid_t pid = (pid_t)strtol(c2 + 1, NULL, 10);
    unsigned long long start = strtoull(c1 + 1, NULL, 10);
    if (pid <= 0)
        return -1;
    unsigned long long now = sys_proc_start(pid);
    return now != 0 && now == start;
}

int sys_ncpu(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n > 0 ? (int)n : 1;
}
