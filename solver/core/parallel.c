/* parallel: MPI start-up and the reductions of replicated-data runs. */
#include "core/parallel.h"

#include <mpi.h>
#include <stdlib.h>
#include <string.h>

static int launched_by_mpirun(void)
{
    return getenv("OMPI_COMM_WORLD_SIZE") || getenv("PMIX_RANK") || getenv("PMI_SIZE");
}

int parallel_init(struct parallel *par, int *argc, char ***argv, struct err *e)
{
    memset(par, 0, sizeof *par);
    par->size = 1;
    if (!launched_by_mpirun())
        return 0;
    if (MPI_Init(argc, argv) != MPI_SUCCESS)
        return err_set(e, ERR_RUNTIME, "MPI_Init failed");
    par->mpi = 1;
    MPI_Comm_rank(MPI_COMM_WORLD, &par->rank);
    MPI_Comm_size(MPI_COMM_WORLD, &par->size);
    return 0;
}

void parallel_finalize(struct parallel *par)
{
    if (par->mpi)
        MPI_Finalize();
    par->mpi = 0;
}

void parallel_sum(const struct parallel *par, double *buf, size_t n)
{
    if (!par || par->size <= 1 || n == 0)
        return;
    /* reduce + broadcast rather than allreduce: all ranks get the same bits */
    const size_t chunk = (size_t)1 << 26;
    for (size_t at = 0; at < n; at += chunk) {
        int len = (int)(n - at < chunk ? n - at : chunk);
        if (par->rank == 0)
            MPI_Reduce(MPI_IN_PLACE, buf + at, len, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
        else
            MPI_Reduce(buf + at, NULL, len, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
        MPI_Bcast(buf + at, len, MPI_DOUBLE, 0, MPI_COMM_WORLD);
    }
}

void parallel_range(const struct parallel *par, int n, int *lo, int *hi)
{
    if (!par || par->size <= 1) {
        *lo = 0;
        *hi = n;
        return;
    }
    *lo = (int)((long)n * par->rank / par->size);
    *hi = (int)((long)n * (par->rank + 1) / par->size);
}

int parallel_any(const struct parallel *par, int flag)
{
    if (!par || par->size <= 1)
        return flag != 0;
    int in = flag != 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, MPI_COMM_WORLD);
    return out;
}
