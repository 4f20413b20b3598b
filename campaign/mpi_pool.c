/* mpi_pool: MPI init/finalize and tagged text messages (the only mpi.h user). */
#include "mpi_pool.h"

#include <mpi.h>
#include <stdlib.h>
#include <string.h>
#include "util/mem.h"

int mpi_pool_wanted(void)
{
    const char *a = getenv("OMPI_COMM_WORLD_SIZE");
    const char *b = getenv("PMIX_RANK");
    return (a && a[0]) || (b && b[0]);
}

int mpi_pool_init(int *argc, char ***argv, int *rank, int *size, struct err *e)
{
    int provided;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        return err_set(e, ERR_RUNTIME, "MPI_Init failed");
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
    return 0;
}

void mpi_pool_finalize(void)
{
    int done = 0;
    MPI_Finalized(&done);
    if (!done)
        MPI_Finalize();
}

void mpi_pool_abort(int code)
{
    MPI_Abort(MPI_COMM_WORLD, code);
}

int mpi_pool_send(int dest, int tag, const char *text, struct err *e)
{
    int len = (int)strlen(text) + 1;
    if (MPI_Send(text, len, MPI_CHAR, dest, tag, MPI_COMM_WORLD) != MPI_SUCCESS)
        return err_set(e, ERR_RUNTIME, "MPI_Send to rank %d failed", dest);
    return 0;
}

int mpi_pool_poll(int *src, int *tag, char **text, struct err *e)
{
    int flag = 0;
    MPI_Status st;
    if (MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &st) != MPI_SUCCESS)
        return err_set(e, ERR_RUNTIME, "MPI_Iprobe failed"), -1;
    if (!flag)
        return 0;
    int n;
    MPI_Get_count(&st, MPI_CHAR, &n);
    char *buf = mem_alloc((size_t)n + 1);
    if (!buf)
        return err_nomem(e, "MPI message"), -1;
    if (MPI_Recv(buf, n, MPI_CHAR, st.MPI_SOURCE, st.MPI_TAG, MPI_COMM_WORLD, MPI_STATUS_IGNORE) !=
        MPI_SUCCESS) {
        free(buf);
        return err_set(e, ERR_RUNTIME, "MPI_Recv failed"), -1;
    }
    buf[n] = '\0';
    *src = st.MPI_SOURCE;
    *tag = st.MPI_TAG;
    *text = buf;
    return 1;
}
