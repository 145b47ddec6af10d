/* contact_law.h — the lubricated contact law (Chèvremont, Bodiguel & Chareyre) as pure
 * per-pair kernels.
 *
 * Reference: ../shared/spec/lubricated-contact-notes.md §1–§4, §11, §12;
 * ../shared/spec/physics-reference.md §5–§6.
 *
 * Units: any consistent set (the engine uses dimensionless units: lengths in units of the
 * mean radius scale, viscosity of the fluid = 1, time set by the scene). Every function here
 * is pure: it reads its inputs, writes only its outputs and the per-pair state it is given,
 * allocates nothing, keeps no global state and is safe to call concurrently on different
 * pairs.
 *
 * Conventions (notes §0.2):
 *  - body 1 and body 2; n points from 1 to (the image of) 2; all forces reported are the
 *    forces ON BODY 1 (body 2 receives the opposite force); compression gives F·n < 0.
 *  - a = (r1 + r2)/2 (arithmetic mean radius) in every formula.
 *  - roughness: PHYSICAL convention, contact when the gap u < eps·a. A value quoted as
 *    "eps" in the seeds (Yade's eps_Y) corresponds to eps = 2·eps_Y here (spec §6, notes §2.11).
 *  - backward Euler (theta = 1) for the normal part, solved with the cancellation-free closed
 *    form and a bracketed log-space fallback; the gap is stored as delta = ln(u/a).
 */
#ifndef LUBDEM_CONTACT_LAW_H
#define LUBDEM_CONTACT_LAW_H

#include "vec3.h"

/* Range of the stored gap delta = ln(u/a) (notes §2.6 item 4, §11 P5/P7).
 *  - No physical floor: in a permanently over-compressed contact (u_n < -alpha eps a; smooth
 *    spheres with u_n < 0) the model's gap decays exponentially for ever and the normal
 *    lubrication force g a R, R = s + alpha_c e - (1 + alpha_c) x, is what carries the load.
 *    delta follows that decay to any depth: x = e^delta may be subnormal or underflow to 0,
 *    which is harmless in the forces (x -> 0), while nu_t and the torques are evaluated from
 *    delta (they grow like -delta and stay finite; the torques are exponentially integrated).
 *  - LUB_DELTA_MIN = -1e7 (u = e^-1e7 a, i.e. 10^-4342945 a) is only a guard that keeps delta
 *    finite under pathological input (h or |s| absurdly large, delta_prev = -inf); no
 *    physical run reaches it (the falling sphere St = 1e4, K = 0.1 trapped by lubrication for
 *    2e5 tau_c reaches delta ~ -1e5). At -1e7 the spacing of doubles in delta is 2e-9, far
 *    below any decay per step that matters.
 *  - LUB_DELTA_MAX = 700 keeps x = e^delta finite (exp overflows above 709.78); a gap of
 *    e^700 a is never reached by a pair inside its cut-off.
 *  - LUB_DELTA_STATIC_FLOOR = -700 (x = 9.9e-305, a normal double) is the gap used ONLY when
 *    there is no normal lubrication (h = +inf: quasi-static balance, no gap dynamics) and the
 *    static balance has no positive root (asperities crushed / smooth overlap: the
 *    "hard-core" case), and as the starting gap of a pair created in that state. */
#define LUB_DELTA_MIN (-1.0e7)
#define LUB_DELTA_MAX (700.0)
#define LUB_DELTA_STATIC_FLOOR (-700.0)
#ifndef LUB_PI
#define LUB_PI 3.14159265358979323846
#endif

/* Term switches (bit mask). Each can be turned off independently for negative tests. */
enum {
    LUB_TERM_NORMAL_LUB = 1u << 0, /* normal lubrication (nu_n = 3/2 pi eta a^2) */
    LUB_TERM_SHEAR_LUB = 1u << 1,  /* tangential (shear) lubrication nu_t(u) */
    LUB_TERM_ROLL = 1u << 2,       /* rolling lubrication torque (u < a only) */
    LUB_TERM_TWIST = 1u << 3,      /* twisting lubrication torque (u < a only) */
    LUB_TERM_FRICTION = 1u << 4,   /* Coulomb friction of rough contacts (tangential contact) */
    LUB_TERM_ALL = 0x1fu
};

/* Law parameters, shared by many pairs. */
typedef struct {
    double eta;     /* fluid viscosity (>= 0) */
    double k_bulk;  /* g: bulk/surface normal stiffness, force per length (> 0) */
    double alpha;   /* k_n/g: asperity-to-bulk stiffness ratio (> 0; Yade uses 1) */
    double k_t;     /* tangential stiffness, force per length (>= 0) */
    double eps;     /* roughness, physical convention: contact when u < eps*a (>= 0) */
    double mu;      /* Coulomb friction coefficient of contacts (>= 0) */
    unsigned terms; /* LUB_TERM_* mask */
} lub_law_params;

/* Persistent per-pair state (64 bytes). Start every pair with lub_pair_state_reset() when it
 * is created (it must be created with a positive centre gap u_n, see notes §11 P3; a
 * non-positive u_n at creation is initialised at the static solution or a positive floor,
 * never NaN). A state that is all zero bits is NOT a new pair: it is a pair at u = a whose
 * x disagrees with delta; only lub_pair_step and lub_pair_step_batch write a non-new state
 * (tests that build one by hand use lub_pair_state_set_gap). */
typedef struct {
    double delta; /* ln(u/a) at the end of the last step (u = true gap, > 0): THE gap state */
    double x;     /* u/a as the law computed it at the end of the last step (= e^delta to
                     round-off; 0 or subnormal where delta < ~-708). The batched law starts its
                     normal solve from it instead of recomputing e^delta. Negative
                     (LUB_PAIR_STATE_NEW) until the pair's first evaluation: the new-pair mark */
    vec3 fs;      /* total shear force on body 1 at the end of the last step */
    vec3 n_prev;  /* unit normal at the end of the last step */
} lub_pair_state;

_Static_assert(sizeof(lub_pair_state) == 64, "one pair state per cache line (README Throughput)");

#define LUB_PAIR_STATE_NEW (-1.0)

/* A new pair: first evaluation next, history not yet defined. */
static inline void lub_pair_state_reset(lub_pair_state *s)
{
    *s = (lub_pair_state){.x = LUB_PAIR_STATE_NEW};
}
/* 1 while the pair has not been evaluated (x negative or NaN). */
static inline int lub_pair_state_is_new(const lub_pair_state *s) { return !(s->x >= 0.0); }

/* Kinematics of one pair for one step (leap-frog half-step velocities). */
typedef struct {
    vec3 branch;   /* d = x2 + H c - x1 (centre of 1 to centre of the interacting image of 2) */
    vec3 v1, v2;   /* translational velocities; v2 INCLUDES the image mean-field shift L H c */
    vec3 w1, w2;   /* angular velocities */
    double r1, r2; /* radii (> 0) */
    double inv_inertia1, inv_inertia2; /* 1/I of each body (0 for a fixed body); used only by
                                          the exponential (stable) integration of the roll/twist
                                          torques. RECOMMENDED: pass N_i/I_i, N_i = number of
                                          pairs of body i (>= 1): each pair then uses the share
                                          I_i/N_i of the inertia and the sum over many stiff
                                          neighbours cannot overshoot (see contact_torque.c and
                                          the README "Contact law"). Torques -> c*Omega when
                                          c dt N/I << 1, whichever is passed. */
    double dt;                         /* time step (> 0) */
} lub_pair_input;

/* Everything a scene, a stress sum or a PDF needs from one evaluation. */
typedef struct {
    vec3 force1;       /* total force on body 1 = (fn_contact + fn_lub) n + fs_contact + fs_lub */
    vec3 torque1;      /* total torque on body 1 (shear-force arm + roll + twist) */
    vec3 torque2;      /* total torque on body 2 */
    vec3 n;            /* unit normal 1 -> 2 */
    double un;         /* centre gap |d| - r1 - r2 */
    double gap;        /* true gap u = a exp(delta) (may underflow to 0; delta stays finite) */
    double delta;      /* ln(u/a) */
    double fn_contact; /* normal contact force along n (<= 0), on body 1 */
    double fn_lub;     /* normal lubrication force along n = g a R+ (exact: never F_n - F_c) */
    vec3 fs_contact;   /* tangential contact (friction) part */
    vec3 fs_lub;       /* tangential lubrication part (consistent: fs = fs_contact + fs_lub) */
    vec3 torque_roll1, torque_twist1; /* lubrication torques on body 1 (body 2 gets minus) */
    int contact;                      /* 1 if u < eps a at the end of the step */
    int slip;                         /* 1 if the contact is sliding */
} lub_pair_output;

/* One step of the full law for one pair. Updates *state. Returns 0 on success, 1 if the
 * result is not finite (out and *state are then written but meaningless), 2 if |branch| is 0
 * or not finite (out zeroed, state untouched); the caller must stop the run with a diagnostic.
 * Switches (p->terms):
 *  - NORMAL_LUB off (or eta = 0): quasi-static normal balance (h = +inf below); fn_lub = 0 and
 *    the whole F_n is the contact force (F_n = 0 out of contact).
 *  - SHEAR_LUB off: nu_t = 0 in every formula: out of contact F_s = 0; in contact pure
 *    elastic-plastic (Cundall) friction.
 *  - FRICTION off: no slider, i.e. mu = 0 / no tangential contact force: the tangential
 *    element is the Maxwell (no-contact) one even in contact; fs_contact = 0, slip = 0.
 *  - ROLL / TWIST off: the corresponding torque is 0. Both exist only for u < a (delta < 0).
 * A new pair (lub_pair_state_is_new) starts at delta = ln(u_n/a) (>= -745 for any positive double
 * u_n/a), or, if u_n <= 0, at the quasi-static solution (LUB_DELTA_STATIC_FLOOR if there is none),
 * with F_s = 0 and n_prev = n; the step then integrates from there. Everything stays finite for any
 * delta: x = e^delta underflowing to 0 gives gap = 0 exactly while delta < 0 stays the (finite)
 * state, nu_t and the torques grow like -delta. */
int lub_pair_step(const lub_law_params *p, const lub_pair_input *in, lub_pair_state *state,
                  lub_pair_output *out);

/* ---- building blocks, exposed for unit tests ---- */

/* Normal part (notes §2.6). Dimensionless: x_prev = u-/a (> 0), s = u_n/a, h = dt g a / nu_n
 * (> 0; h = +INFINITY when normal lubrication is off), e = eps, alpha = k_n/g.
 * Returns delta+ = ln(x+) of the unique root of the backward-Euler equation, computed in log
 * form (no floor: x+ = e^delta+ may be far below DBL_MIN), clamped only to the guard range
 * [LUB_DELTA_MIN, LUB_DELTA_MAX]; never NaN for finite inputs. *contact (may be NULL) set to
 * 1 if x+ < e (i.e. delta+ < ln e; never for e = 0, even when x+ underflows to 0).
 * delta_prev is ln(x_prev), passed in log form so that x_prev may be far below DBL_MIN (any
 * finite delta_prev is accepted; a compressed pair keeps decaying, notes §11 P5).
 * h = +INFINITY: x solves (1 + a_c) x = s + a_c e. When that has no positive solution
 * (s <= -alpha e; with e = 0: s <= 0 — asperities fully crushed or smooth spheres
 * overlapping without lubrication), or its solution is below e^LUB_DELTA_STATIC_FLOOR, the gap
 * is held at the fixed floor LUB_DELTA_STATIC_FLOOR (no dynamics to follow), *contact = 1 and
 * lub_pair_step reports the whole F_n = g a (s - x) (stiffness g) as contact force. */
double lub_normal_solve(double delta_prev, double s, double h, double e, double alpha,
                        int *contact);

/* The same root by a bracketed bisection/Newton in log space (reference solver for tests and
 * the fallback when the closed form underflows). The objective is evaluated with differences
 * of delta only (e^{delta_prev - delta}, expm1), so any finite delta_prev works. Stops on a
 * certified bracket width <= 1e-14 + 4 DBL_EPSILON |delta| in delta; same guard clamp as
 * lub_normal_solve (h = +INFINITY: the root of R = 0, held at LUB_DELTA_STATIC_FLOOR when it
 * is below, as in lub_normal_solve). */
double lub_normal_solve_bracketed(double delta_prev, double s, double h, double e, double alpha);

/* Dimensionless rate R = s + alpha_c e - (1 + alpha_c) x with x = exp(delta) (notes §2.2). */
double lub_normal_rate(double delta, double s, double e, double alpha);

/* Tangential lubrication coefficient nu_t(u) = (pi eta a / 2)[-2 + (2 + x)(ln(2 + x) - delta)],
 * evaluated from delta for any gap (notes §3.1). */
double lub_shear_viscosity(double eta, double a, double delta);

/* An evaluated state at gap delta (x = e^delta), for tests and tools that build states by
 * hand; fs and n_prev are left as they are. */
void lub_pair_state_set_gap(lub_pair_state *s, double delta);

/* Human-readable names of the active terms, for summaries. Writes up to max names and
 * returns how many were written. */
int lub_terms_names(unsigned terms, const char **names, int max);

#endif
