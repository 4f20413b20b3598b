/*
 * handshake: the MPM/MD handshake of Guo & Yang 2005, section 2.2 (Fig. 3).
 *
 * An axis-aligned box B of cubic crystal (fcc, bcc or diamond, cube axes
 * along x, y, z) is molecular dynamics; the material
 * point method covers a larger box D around it on a background grid that
 * coarsens hierarchically away from B (Fig. 1(c), section 2.1).  Every face
 * of B strictly inside D is an interface, and along it lie
 *
 *   region I    atoms inside B within w_I of the interface: integrated by
 *               MD, and in the MPM step also material points that give the
 *               grid their mass, momentum and virial stress (Chen 2014 step
 *               s3a) without following the grid;
 *   region II   material points on the lattice sites within w_II outside B,
 *               moved by the grid, and atoms for the MD forces: they are
 *               the neighbours of region I and give it its EAM electron
 *               density atmosphere (Eq. (13));
 *   region III  the next w_III of lattice-site material points: the
 *               atmosphere of region II.
 *
 * The copies of regions II and III are ordinary particles of the MD force
 * loop, frozen in the integrator: every pair, three-body (sw, meam/spline)
 * and embedding term in which a region I atom takes part is computed in
 * full, also the triplets centred on a region II copy whose other leg is a
 * copy (which region I does not see directly); the forces on the copies
 * are computed and discarded, their energies belong to no one.  Regions II
 * and III together span two cutoffs, the reach of such terms.
 *
 * Each width is at least one potential cutoff.  Faces of B on the boundary
 * of D are MD boundaries (periodic, as the lateral faces of the bar, or
 * free, as the top of an impact target).  In cells of the finest level the
 * MPM points sit on the lattice sites (cells of one lattice constant: the
 * four fcc, two bcc or eight diamond sites, atomic mass and volume each) or,
 * for fcc only, at the cell centres (cells of half a lattice constant:
 * every other centre is a site; each point has half an atomic mass and
 * volume); in coarse cells eight points sit at the reduced
 * coordinates (+-1/2, +-1/2, +-1/2) with mass in proportion to the cell
 * volume (section 2.2, last paragraph).  The MPM material is cubic elastic
 * with C11, C12, C44 of the same potential.
 *
 * One step of common length dt (section 2.2, "one concurrent time step"):
 *   1. region I's positions, velocities and virial stresses at t go to the
 *      MPM as an extra particle set;
 *   2. one MUSL step of the MPM moves regions II, III and the rest to t+dt;
 *   3. the MD copies of regions II and III take the positions at t+dt
 *      (displacement coupling; they are frozen in the MD integrator);
 *   4. one velocity-Verlet step of the MD: forces at t+dt see regions II
 *      and III where the MPM put them.
 *
 * Groups: atoms carry HS_MASK_I (region I) and the MD copies of regions II
 * and III HS_MASK_II / HS_MASK_III; MPM points carry the same bits.  Every
 * MD particle has a per-particle field "region" (enum hs_region), written to
 * the HDF5 snapshots, so ParaView can colour the regions.
 */
#ifndef CASCADE_HANDSHAKE_H
#define CASCADE_HANDSHAKE_H

#include <stdint.h>

#include "md/md.h"
#include "mpm/mpm.h"
#include "output/checkpoint.h"
#include "util/err.h"

enum {
    HS_MASK_I = 1u << 8,
    HS_MASK_II = 1u << 9,
    HS_MASK_III = 1u << 10,
    HS_MASK_FIXED = 1u << 11,   /* MD atoms held at their sites (e.g. a far end) */
    HS_MASK_SITE = 1u << 12,    /* a material point on a lattice site (has an MD copy
                                   when in region II or III) */
};

/* Region codes of the "region" output field. */
enum hs_region { HS_CORE = 0, HS_I = 1, HS_II = 2, HS_III = 3, HS_MPM = 4, HS_FIXED = 5 };

/* The cubic crystals the handshake handles.  Zero is fcc, so a layout
 * cleared with memset is the fcc one it always was. */
enum hs_lattice { HS_LATTICE_FCC = 0, HS_LATTICE_BCC, HS_LATTICE_DIAMOND, HS_LATTICE_COUNT };
extern const char *const hs_lattice_names[];   /* "fcc", "bcc", "diamond", NULL */

/* Sites of the cubic cell (fractions of a), at most 8; returns how many. */
int hs_lattice_basis(enum hs_lattice l, double basis[8][3]);

/* Where the sites sit relative to the grid planes: the lattice origin lies
 * this many lattice constants off a grid plane (a/4 for fcc and bcc, a/8
 * for diamond, whose sites are a/4 apart along an axis).  No site then lies
 * on a cell face of a or a/2. */
double hs_lattice_offset(enum hs_lattice l);

/* Orientations of the crystal in the box.  Zero is [100] (cube axes along
 * x, y, z), so a layout cleared with memset keeps it.  [110]: x along
 * [110], y along [-110], z along [001]. */
enum hs_orientation { HS_ORIENT_100 = 0, HS_ORIENT_110, HS_ORIENT_COUNT };
extern const char *const hs_orientation_names[];   /* "100", "110", NULL */

/* The crystal directions along x, y, z (rows, unit vectors in cube
 * coordinates). */
void hs_orientation_axes(enum hs_orientation o, double R[3][3]);

/* The orthogonal repeat cell of lattice l in orientation o: its edges
 * (period[d], in lattice constants: 1, 1, 1 along [100]; fcc and diamond
 * along [110] a/sqrt2, a/sqrt2, a; bcc along [110] sqrt2 a, sqrt2 a, a)
 * and its sites (fractions of the edges, at most 8); returns how many. */
int hs_cell_basis(enum hs_lattice l, enum hs_orientation o, double basis[8][3],
                  double period[3]);

/* hs_lattice_offset per axis of the oriented cell, as a fraction of its
 * edge: an eighth where the sites are a quarter edge apart, else a
 * quarter. */
double hs_cell_offset(enum hs_lattice l, enum hs_orientation o, int d);

/* Longitudinal modulus along x (cl) and the moduli coupling x to y and to
 * z (uniaxial strain along x: sigma_yy = cxy eps, sigma_zz = cxz eps) of a
 * cubic crystal in orientation o: C11, C12, C12 along [100]; along [110]
 * (C11 + C12 + 2 C44) / 2, (C11 + C12 - 2 C44) / 2, C12. */
void hs_oriented_moduli(enum hs_orientation o, double c11, double c12, double c44, double *cl,
                        double *cxy, double *cxz);

/* Where things are (all lengths in Å). */
struct handshake_layout {
    enum hs_lattice lattice;   /* fcc (0), bcc or diamond                       */
    enum hs_orientation orient;   /* [100] (0) or [110] along x                 */
    double a;                  /* cubic lattice constant                        */
    double lat_origin[3];      /* one lattice site                              */
    double dom_lo[3], dom_hi[3];   /* MPM domain D (the grid)                   */
    double mat_lo[3], mat_hi[3];   /* the material inside D (points only there;
                                      empty cells beyond a free end give it room) */
    double md_lo[3], md_hi[3];     /* MD box B                                  */
    int md_periodic[3];        /* MD periodic along an axis where B spans D     */
    double w[3];               /* widths of regions I, II, III                  */
    double h;                  /* finest cell edge along x; along y and z the
                                  same fraction of the oriented cell's edge     */
    double fine;               /* distance from B to the first coarse cell      */
    int nlevels;               /* coarsening levels (0: uniform grid)           */
    unsigned coarsen;          /* directions halved per level (x 1, y 2, z 4)   */
    double layer;              /* width of each coarse level before the next    */
    enum mpm_face_bc face[6];  /* grid faces x_lo x_hi y_lo y_hi z_lo z_hi      */
};

/* Which layout key a refusal is about (for file/line/key messages). */
enum hs_layout_key {
    HS_KEY_REGIONS, HS_KEY_CELL, HS_KEY_FINE, HS_KEY_LEVELS, HS_KEY_LAYER,
    HS_KEY_GEOMETRY,   /* the MPM domain and material */
    HS_KEY_MD,         /* the MD region */
    HS_KEY_COUNT
};

/* Check a layout against the potential cutoff (Å): each region at least one
 * cutoff wide, region I at least two cells (so that no node that moves a
 * region II point sees the inner edge of region I), the MD region and its
 * regions II and III on the finest grid, cells and faces aligned.  On
 * refusal fills *key and `why`. */
int handshake_layout_check(const struct handshake_layout *L, double cutoff,
                           enum hs_layout_key *key, char *why, size_t len);

/* The oriented cell's edges (Å) and the finest grid cell's edges (Å). */
void handshake_layout_period(const struct handshake_layout *L, double p[3]);
void handshake_layout_cell(const struct handshake_layout *L, double h[3]);

/* Whether face f (0..5) of B is an interface (strictly inside the material). */
int handshake_face_coupled(const struct handshake_layout *L, int f);

/* Region of a lattice site at x: HS_CORE / HS_I inside B, HS_II / HS_III in
 * the shells outside the coupled faces (Chebyshev distance), HS_MPM
 * beyond. */
enum hs_region handshake_classify(const struct handshake_layout *L, const double x[3]);

/* The MPM material constants (eV/Å^3) and the crystal (amu, eV). */
struct handshake_crystal {
    char element[16];
    double mass;          /* atomic mass */
    int type;             /* particle type of the atoms */
    double pe_ref;        /* per-atom energy of the perfect crystal (-E_coh) */
    double c11, c12, c44; /* of the MPM material; C44 the relaxed one (diamond:
                             the sublattice shift free, as in the MD) */
    double c44_unrelaxed; /* diamond with both sublattices affine (else = c44) */
    double zeta;          /* Kleinman's internal-strain parameter of diamond (else 0):
                             region II and III copies take the shift of their
                             point's strain (hs_internal_shift) */
};

/* Diamond's internal strain in the handshake.  The MPM field is the
 * displacement of the sublattices' mean; under a shear in the cube axes
 * the second fcc sublattice (at (1/4, 1/4, 1/4) a from the first) shifts
 * against the first by u = -zeta (a/4) (gamma_yz, gamma_xz, gamma_xy)
 * (Kleinman 1962; md/crystal.h).  A site of the first sublattice sits at
 * -u/2 from its point's position, one of the second at +u/2, so the copies
 * of regions II and III meet region I's atoms as the relaxed crystal does.
 *
 * hs_sublattice: -1 (first) or +1 (second) for a diamond site with
 * reference position x0 (the layout's lat_origin a site of the first), 0
 * for other lattices and for points off the sites.
 * hs_internal_shift: the site's displacement from its point (Å, box frame)
 * under the deformation gradient F (row-major, box frame), from the small
 * strain sym(F) - I turned to the cube axes.
 * Both take the crystal axes hs_orientation_axes(L->orient) as `axes`,
 * computed once (struct handshake's axes), not per site and step. */
int hs_sublattice(const struct handshake_layout *L, const double axes[3][3],
                  const double x0[3]);
void hs_internal_shift(const struct handshake_layout *L, const double axes[3][3], double zeta,
                       int sublattice, const double F[9], double dx[3]);

/* Doubles in a copy's row (struct handshake's link_row): position x[3]
 * (where the copy sits: the point's position plus diamond's internal
 * shift, wrapped), the point's velocity v[3] and its strain energy eint. */
#define HS_LINK_ROW 7

struct hs_thermal;
struct hs_bricks;
struct handshake;

/* Point the MPM's extra set at the n region I rows of xI, vI, mI, sI and
 * volI (this rank's atoms; on bricks the node sums add the others'). */
void hs_extra_region_i(struct handshake *hs, long n);

struct handshake {
    struct handshake_layout lay;
    struct handshake_crystal cr;
    double axes[3][3];         /* hs_orientation_axes(lay.orient), set once by
                                  handshake_create (hs_internal_shift) */
    struct md *md;             /* borrowed (see handshake_create) */
    struct mpm mpm;
    double omega0;             /* atomic volume a^3 / (sites per cubic cell) */
    double rho;                /* amu/Å^3 */
    int body;                  /* MPM body of all points */
    int f_region, f_x0;        /* MD particle fields "region", "reference_position" */
    int64_t id_base;           /* MD id of the copy of point q: id_base + q */
    /* region I as an MPM extra set (compact copies refreshed every step) */
    struct mpm_extra extra;
    long nI;
    int *idxI;
    double *xI, *vI, *mI, *sI, *volI;
    /* MD copies of regions II and III: MD particle -> MPM point */
    long nlink;
    int *link_md;
    long *link_pt;             /* the point's index among the points of all ranks */
    double *link_row;          /* HS_LINK_ROW per copy: its point's row (position where
                                  the copy goes, velocity, strain energy), refreshed
                                  after every MPM step (handshake_bricks.h) */
    long npoints;              /* material points of all ranks (on bricks each rank
                                  holds its share in mpm.pts) */
    long seen_builds;          /* md->nrebuilds when the index lists were made */
    struct hs_bricks *bricks;  /* MD on bricks: the points' owners and the copies' rows
                                  (handshake_bricks.h); NULL otherwise */
    long natoms;               /* MD atoms (core, I and fixed) */
    long counts[6];            /* per enum hs_region: atoms (0, 1, 5) or points */
    long ncopies;              /* MD copies of the lattice-site points of II, III */
    double md_damping;         /* 1/ps: velocity damping of the MD atoms (quasi-static) */
    double ramp;               /* ps: external point forces reach full value after this */
    struct hs_thermal *thermal;   /* borrowed; NULL: 0 K, copies on their points
                                     (handshake_thermal.h) */
    long step;
    double time;               /* ps */
};

/* Build the MPM side (grid, material, points) of layout L and append the
 * MD particles to *p (created when NULL): when it is empty, the atoms of B
 * with their regions, then the copies of regions II and III.  When *p already holds
 * the atoms of B (a case that built its own crystal on the same lattice),
 * only the copies are appended and the atoms' regions marked; atoms beyond
 * the MPM material (a projectile above a free face) are plain MD atoms
 * (HS_CORE), atoms inside it but outside B are refused.  After
 * md_init(md, *p, ...) call handshake_connect. */
int handshake_create(struct handshake *hs, const struct handshake_layout *L,
                     const struct handshake_crystal *cr, struct particles **p, int nthreads,
                     struct err *e);

/* handshake_create in two halves, for a case on MPI bricks (core/halo.h)
 * that builds the MPM before it knows its brick and its atoms after:
 * handshake_build_mpm is the MPM side (grid, material, every point; on
 * bricks handshake_connect then keeps this rank's share of the points,
 * handshake_bricks.h), handshake_add_particles the MD side over
 * the case's own atoms in *p.  With a halo, *p holds the rank's atoms,
 * only the copies whose point lies in the rank's brick are appended (ids
 * as in a serial build), and the counts of atoms and copies are the sums
 * over the ranks.  Collective when halo is given. */
struct halo;
int handshake_build_mpm(struct handshake *hs, const struct handshake_layout *L,
                        const struct handshake_crystal *cr, int nthreads, struct err *e);
int handshake_add_particles(struct handshake *hs, struct particles **p, const struct halo *halo,
                            struct err *e);

/* Everything in one call for cases that own the MD: handshake_create with
 * a new particle set, md_init over it (md takes ownership of pot; the box
 * is periodic where L says so and free elsewhere), handshake_connect. */
int handshake_setup(struct handshake *hs, struct md *md, const struct handshake_layout *L,
                    const struct handshake_crystal *cr, struct potential *pot, double dt,
                    double skin, int nthreads, struct err *e);

/* The MD box of handshake_setup: B along periodic axes, B and the shell
 * of regions II and III (free) along the others. */
void handshake_md_box(const struct handshake_layout *L, struct box *box);

/* handshake_setup on MPI bricks (core/halo.h; docs/parallel.md, "How the
 * handshake bar cases run on bricks"): the MPM side built whole on every
 * rank (handshake_connect deals its points out, handshake_bricks.h),
 * the atoms of B whose sites lie in this rank's brick and the copies whose
 * points lie in it (ids of a serial build), md_adopt and md_init over them
 * (the box of handshake_md_box; with `balance` the cuts shifted to even
 * the particles, halo_balance), handshake_connect.  pot and halo are the
 * md's from the call on (freed with it, or here on a failure before md_init
 * takes them).  Collective over the halo's ranks. */
int handshake_setup_bricks(struct handshake *hs, struct md *md, const struct handshake_layout *L,
                           const struct handshake_crystal *cr, struct potential *pot, double dt,
                           double skin, int nthreads, struct halo *halo, int balance,
                           struct err *e);

/* The crystal of a potential for the handshake: 0 K lattice constant in
 * [a_min, a_max] (*a0), cohesive energy, cubic elastic constants and the
 * atomic mass of `element` (from the potential file, else the standard
 * mass).  The type is left 0.  handshake_crystal_from_potential is the fcc
 * crystal. */
int handshake_crystal_of_lattice(struct potential *pot, enum hs_lattice lattice,
                                 const char *element, double a_min, double a_max,
                                 struct handshake_crystal *cr, double *a0, struct err *e);
/* Diamond's zeta (*zeta; 0 for other lattices) of the potential's crystal
 * cr at the lattice constant a, e.g. a(T) of an MD region at T: the
 * relaxed sublattice shift of the static crystal at that a (the MPM's C44
 * at T, from MD averages, is the relaxed one by construction). */
int handshake_crystal_zeta_at(struct potential *pot, enum hs_lattice lattice,
                              const struct handshake_crystal *cr, double a, double *zeta,
                              struct err *e);
int handshake_crystal_from_potential(struct potential *pot, const char *element, double a_min,
                                     double a_max, struct handshake_crystal *cr, double *a0,
                                     struct err *e);

/* Tie the handshake to the md that now owns the particles: freeze the
 * copies, switch on per-atom virials, keep the particle order, on bricks
 * keep this rank's share of the material points (handshake_bricks.h),
 * find the index lists and attach region I to the MPM; recomputes the
 * forces.  Collective on bricks. */
int handshake_connect(struct handshake *hs, struct md *md, struct err *e);

/* One coupled step (see the top of this file): MPM from t to t+dt, regions
 * II/III to the MD, one MD step.  md->dt is the common step. */
int handshake_step(struct handshake *hs, struct err *e);

/* The MPM half of a step: region I -> MPM, MPM step, II/III -> MD.  For
 * callers that run md_step themselves (call it before each md_step). */
int handshake_advance_mpm(struct handshake *hs, struct err *e);

/* The end of a step, after the MD's second half kick: the damping of the
 * atoms (md_damping) and the step and time counters.  handshake_step is
 * handshake_advance_mpm, md_step, handshake_finish_step; the engine runs
 * the same sequence as stages (engine/model_handshake.c). */
void handshake_finish_step(struct handshake *hs);

/* Checkpoints (output/checkpoint.h): the MPM side (every material point
 * array, the MPM's clock and energy sums) and the handshake's counters,
 * under group `group`; the MD atoms are the MD model's.  The points are
 * built from the case file first: a read replaces their state, not their
 * number.  After a write (in the continuing run) and after a read (in the
 * restarted one), handshake_checkpoint_sync puts both in the same state:
 * the points are located afresh and region I and the copies indexed anew
 * at the next step, as the MD rebuilds its lists (md->rebuild_next).  The
 * cluster-impact boundary can use these with the MD model's checkpoint. */
int handshake_checkpoint_write(const struct handshake *hs, struct ckpt *ck, const char *group);
/* Before rank 0 writes, on every rank (collective on bricks: every rank's
 * count of points, for the layout rank 0 writes). */
int handshake_checkpoint_collect(struct handshake *hs, struct err *e);
/* On bricks, after rank 0 wrote and closed the file, on every rank with
 * the file open through MPI-IO: this rank's points into their rows of
 * `group`.  Collective; 0 serially. */
int handshake_checkpoint_write_part(const struct handshake *hs, struct ckpt *ck,
                                    const char *group);
int handshake_checkpoint_read(struct handshake *hs, struct ckpt *ck, const char *group);
void handshake_checkpoint_sync(struct handshake *hs);

void handshake_free(struct handshake *hs);

/* Energies (eV): MD atoms of B (kinetic, potential relative to the perfect
 * crystal, fixed atoms left out) and MPM points (kinetic, strain). */
struct handshake_energy {
    double md_kinetic, md_potential, mpm_kinetic, mpm_strain, total;
};
void handshake_energy(const struct handshake *hs, struct handshake_energy *out);

/* Potential part of the virial stress of MD particle i (eV/Å^3, xx yy zz
 * xy xz yz) over the atomic volume: what region I gives the MPM. */
static inline void handshake_atom_stress(const struct handshake *hs, int i, double s[6])
{
    const double *w = hs->md->p->virial + 6 * i;
    for (int c = 0; c < 6; c++)
        s[c] = -w[c] / hs->omega0;
}

/* Impose the homogeneous strain x = X + diag(eps) (X - origin) on every
 * atom and material point (MD box lengths of periodic axes included), with
 * F, volume and stress of the points from their material law, and
 * diamond's sublattices (atoms and copies) shifted by hs_internal_shift,
 * then recompute the MD forces.  For tests of the coupling's consistency. */
int handshake_apply_strain(struct handshake *hs, const double eps[3], const double origin[3],
                           struct err *e);

/* Map the current state to the grid (s1-s3 with region I), without moving
 * anything: the nodal forces of that state are then in mpm.grid.node[].f. */
int handshake_map_forces(struct handshake *hs, struct err *e);

/* Wrap x into the MD box along periodic axes. */
void handshake_wrap(const struct handshake *hs, double x[3]);

#endif
