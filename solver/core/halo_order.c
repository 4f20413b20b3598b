/* halo_order: where a rank's ids fall in the order of all ranks' ids
 * (halo.h, halo_id_positions). */
#include "core/halo.h"

#include <stdlib.h>
#include <string.h>

#include "core/parallel.h"

int halo_id_positions(const struct halo *h, const int64_t *ids, int n, long *pos, long *shared,
                      struct err *e)
{
    if (shared)
        *shared = 0;
    for (int k = 0; k < n; k++)
        pos[k] = k;   /* own ids: sorted and unique */
    const struct parallel *par = h->dc.par;
    int nranks = halo_nranks(h);
    if (nranks == 1)
        return 0;
    /* every rank's sorted list travels once round the ring; at each hop a
     * rank merges the list it holds against its own, counting the smaller
     * ids (O(all ids) work, O(brick) memory) */
    size_t scap = (size_t)(n ? n : 1) * sizeof *ids, rcap = 0, sbytes = (size_t)n * sizeof *ids;
    void *sbuf = malloc(scap), *rbuf = NULL;
    int rc = sbuf ? 0 : err_nomem(e, "id order");
    if (sbuf && n)
        memcpy(sbuf, ids, sbytes);
    if (parallel_any(par, rc != 0) && !rc)
        rc = err_set_elsewhere(e, ERR_RUNTIME, "stopped: another MPI rank failed");
    int next = (par->rank + 1) % nranks, prev = (par->rank + nranks - 1) % nranks;
    for (int hop = 1; !rc && hop < nranks; hop++) {
        size_t rbytes = 0;
        rc = parallel_sendrecv(par, next, sbuf, sbytes, prev, &rbuf, &rcap, &rbytes, e);
        if (rc)
            break;
        const int64_t *other = rbuf;
        long m = (long)(rbytes / sizeof *other), j = 0;
        for (int k = 0; k < n; k++) {
            while (j < m && other[j] < ids[k])
                j++;
            pos[k] += j;
            if (shared && j < m && other[j] == ids[k])
                ++*shared;
        }
        /* pass on what was received */
        void *t = sbuf;
        size_t tc = scap;
        sbuf = rbuf;
        scap = rcap;
        rbuf = t;
        rcap = tc;
        sbytes = rbytes;
    }
    free(sbuf);
    free(rbuf);
    return rc;
}
