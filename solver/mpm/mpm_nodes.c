/*
 * mpm_nodes: the grid stages of a step.
 *
 * mpm_update_grid, Chen 2014 s4-s5: f_i = f_int + f_ext (s4), the nodal
 * momentum update q_i += f_i dt (s5), kept as the velocity q_i / m_i and the
 * acceleration f_i / m_i that s6-s7 map back.  Nodes whose mass is below
 * the small-mass threshold are skipped, as the paper does ("the solutions
 * from the equations in which m_i appears in the denominator are not
 * used"): their velocity and acceleration are zero.  Nodes touched by a
 * rigid body take its velocity; the force that takes is the body's reaction.
 * Essential boundary conditions (fixed, sliding faces) zero the constrained
 * components.  Velocity damping subtracts alpha v_i from the acceleration.
 *
 * mpm_update_grid_velocity, s11: v_i = (m v)_i / m_i from the remapped
 * momenta of s10, then the boundary conditions again (step 7 of the paper).
 * mpm_step zeroes the fused pass's second node buffer in the same loop
 * (mpm_update_grid_velocity_clearing): one loop over the nodes and one
 * parallel region fewer per step than a separate clear.
 */
#include <math.h>
#include <string.h>

#include "core/units.h"
#include "mpm/mpm_view.h"

/* v = +0.0, written only when its bits are not those of +0.0 already: a
 * node no particle of this rank touched stays unwritten, and its page
 * need not become resident (mpm_grid.h, the node store) */
static inline void zero_component(double *v)
{
    if (*v != 0.0 || signbit(*v))
        *v = 0.0;
}

static void apply_bc(const struct mpm_grid *g, double *a, double *b, int stride_a, int stride_b)
{
    for (long k = 0; k < g->nbc; k++) {
        long i = g->bc_node[k];
        unsigned bits = g->bc_bits[k];
        for (int d = 0; d < 3; d++)
            if (bits & (1u << d)) {
                if (a)
                    zero_component(&a[i * stride_a + d]);
                if (b)
                    zero_component(&b[i * stride_b + d]);
            }
    }
}

void mpm_update_grid(struct mpm *m, double dt)
{
    struct mpm_grid *g = &m->grid;
    struct mpm_node *node = g->node;
    double *r = g->r;
    const int32_t *act = g->active;   /* NULL: every node */
    const uint8_t *first = act ? g->active_first : NULL;   /* the reactions' nodes */
    long n = act ? g->nactive : g->nnodes;
    double small = m->small_mass, alpha = m->damping;
    int nb = m->nbody;
    double react[3 * MPM_MAX_BODIES];
    memset(react, 0, sizeof react);
    double vb[3 * MPM_MAX_BODIES];
    for (int b = 0; b < nb; b++)
        for (int d = 0; d < 3; d++)
            vb[3 * b + d] = m->body[b].velocity[d];
#pragma omp parallel for schedule(static) num_threads(m->nthreads) \
    reduction(+ : react[:3 * MPM_MAX_BODIES])
    for (long k = 0; k < n; k++) {
        long i = act ? act[k] : k;
        struct mpm_node *nd = &node[i];
        r[4 * i + 0] = r[4 * i + 1] = r[4 * i + 2] = r[4 * i + 3] = 0.0;
        double mi = nd->m;
        if (!(mi > small)) {   /* small-mass rule */
            nd->q[0] = nd->q[1] = nd->q[2] = 0.0;
            nd->f[0] = nd->f[1] = nd->f[2] = 0.0;
            continue;
        }
        double inv = 1.0 / mi;
        double v0 = nd->q[0] * inv, v1 = nd->q[1] * inv, v2 = nd->q[2] * inv;
        if (nd->aux > 0) {
            int b = (int)nd->aux - 1;
            double a0 = (vb[3 * b + 0] - v0) / dt, a1 = (vb[3 * b + 1] - v1) / dt,
                   a2 = (vb[3 * b + 2] - v2) / dt;
            if (!first || first[k]) {   /* a node shared by ranks counts once */
                react[3 * b + 0] += mi * a0 * UNITS_MVV2E - nd->f[0];
                react[3 * b + 1] += mi * a1 * UNITS_MVV2E - nd->f[1];
                react[3 * b + 2] += mi * a2 * UNITS_MVV2E - nd->f[2];
            }
            nd->q[0] = vb[3 * b + 0];
            nd->q[1] = vb[3 * b + 1];
            nd->q[2] = vb[3 * b + 2];
            nd->f[0] = a0;
            nd->f[1] = a1;
            nd->f[2] = a2;
            continue;
        }
        /* Eq. (s4)-(s5): a_i = f_i / m_i, v_i(t + dt) = (q_i + f_i dt) / m_i */
        double s = inv * UNITS_FTM2V;
        double a0 = nd->f[0] * s - alpha * v0, a1 = nd->f[1] * s - alpha * v1,
               a2 = nd->f[2] * s - alpha * v2;
        nd->q[0] = v0 + a0 * dt;
        nd->q[1] = v1 + a1 * dt;
        nd->q[2] = v2 + a2 * dt;
        nd->f[0] = a0;
        nd->f[1] = a1;
        nd->f[2] = a2;
    }
    /* essential boundary conditions on the updated velocity and acceleration */
    apply_bc(g, &node[0].q[0], &node[0].f[0], (int)(sizeof *node / sizeof(double)),
             (int)(sizeof *node / sizeof(double)));
    for (int b = 0; b < nb; b++)
        for (int d = 0; d < 3; d++)
            m->body[b].reaction[d] = react[3 * b + d];
}

void mpm_update_grid_velocity(struct mpm *m)
{
    mpm_update_grid_velocity_clearing(m, NULL);
}

void mpm_update_grid_velocity_clearing(struct mpm *m, struct mpm_node *clear)
{
    struct mpm_grid *g = &m->grid;
    const struct mpm_node *node = g->node;
    double *r = g->r;
    /* the fused pass's buffer is cleared whole, so every node is visited */
    const int32_t *act = clear ? NULL : g->active;
    long n = act ? g->nactive : g->nnodes;
    double small = m->small_mass;
#pragma omp parallel for schedule(static) num_threads(m->nthreads)
    for (long k = 0; k < n; k++) {
        long i = act ? act[k] : k;
        if (clear)   /* the fused pass's second buffer, zeroed on the way */
            memset(&clear[i], 0, sizeof clear[i]);
        const struct mpm_node *nd = &node[i];
        double mi = nd->m;
        if (!(mi > small)) {
            r[4 * i + 0] = r[4 * i + 1] = r[4 * i + 2] = r[4 * i + 3] = 0.0;
            continue;
        }
        if (nd->aux > 0) {   /* rigid: its velocity, as after s5 */
            r[4 * i + 0] = nd->q[0];
            r[4 * i + 1] = nd->q[1];
            r[4 * i + 2] = nd->q[2];
            continue;
        }
        double inv = 1.0 / mi;   /* Eq. (s11) */
        r[4 * i + 0] *= inv;
        r[4 * i + 1] *= inv;
        r[4 * i + 2] *= inv;
    }
    apply_bc(g, r, NULL, 4, 0);
}
