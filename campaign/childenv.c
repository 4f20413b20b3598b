/* childenv: environ minus the variables of the runner's own MPI job. */
#include "childenv.h"

#include <stdlib.h>
#include <string.h>
#include "util/mem.h"

extern char **environ;

int childenv_is_mpi(const char *entry)
{
    if (strncmp(entry, "OMPI_ALLOW_RUN_AS_ROOT=", 23) == 0 ||
        strncmp(entry, "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=", 31) == 0)
        return 0;
    return strncmp(entry, "OMPI_", 5) == 0 || strncmp(entry, "PMIX_", 5) == 0;
}

int childenv_is_fault(const char *entry)
{
    return strncmp(entry, "CASCADE_FAULT_", 14) == 0;
}

char **childenv_create(void)
{
    size_t n = 0;
    while (environ[n])
        n++;
    char **env = mem_alloc((n + 1) * sizeof *env);
    if (!env)
        return NULL;
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        if (!childenv_is_mpi(environ[i]) && !childenv_is_fault(environ[i]))
            env[k++] = environ[i];
    env[k] = NULL;
    return env;
}
