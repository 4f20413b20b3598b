/*
 * sysinfo: clocks, the host name and the identity of a runner process
 * ("host:pid:start", where start is the process start time in clock ticks
 * since boot, so a reused pid is not mistaken for a live runner).
 */
#ifndef CASCADE_CAMPAIGN_SYSINFO_H
#define CASCADE_CAMPAIGN_SYSINFO_H

#include <stddef.h>
#include <sys/types.h>

/* Wall-clock Unix time, seconds. */
double sys_now(void);
/* Monotonic clock, seconds. */
double sys_mono(void);
/* ISO 8601 UTC with milliseconds: "2024-05-01T12:00:00.123Z". */
void sys_iso_time(double unix_time, char *buf, size_t len);
void sys_hostname(char *buf, size_t len);
/* Start time of a process (ticks since boot), 0 when it does not exist. */
unsigned long long sys_proc_start(pid_t pid);
/* This process as a runner id: "host:pid:start". */
void sys_runner_id(char *buf, size_t len);
/* Whether a runner id names a process alive on this host.  Returns 1 alive,
 * 0 dead, -1 unknown (another host or an id of another shape). */
int sys_runner_alive(const char *runner_id);
/* Number of online processors (at least 1). */
int sys_ncpu(void);

#endif
