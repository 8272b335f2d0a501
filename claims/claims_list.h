/* The list of claims (CLAIMS.md), for claims.h and claims.c. */
#ifndef CB_CLAIMS_LIST_H
#define CB_CLAIMS_LIST_H

/* The claims, one X(...) entry each, in the report's order:
 *   X(checker, id, experiment, claim, decided by, figures)
 * The checker is a function of type cb_claim_check in
 * claims/check_<experiment>.c; its entry here declares it (claims.h) and
 * lists it in cb_claims[] (claims.c). A new claim is its checker and its
 * entry. */
#define CB_CLAIMS(X) \
  X(cb_check_T1, "T1", "topology", \
    "Sorting edge triples (i<j, triangle) gives the unique edge list and the neighbouring-triangle pairs.", \
    "On the lecture's 5-vertex example: edges {0,1},{0,3},{0,4},{1,2},{1,3},{2,3},{3,4}; neighbour pairs " \
    "{1,2},{0,1}.", \
    NULL) \
  X(cb_check_T2, "T2", "topology", \
    "A manifold disk mesh has #edges = 3 #vertices - 3 - #boundary_edges; with every edge a hard constraint only 3 + " \
    "#boundary_edges DoFs remain.", \
    "Counted on grids and on unstructured meshes; the DoFs as 3#V - rank of the rigidity matrix at a generic " \
    "embedding.", \
    NULL) \
  X(cb_check_E1, "E1", "explicit_stability", "Explicit integration becomes unstable when k and/or dt are too large.", \
    "(k, dt) stability map; measured critical dt within 15% of 2/omega_max at the state the runs start from (the " \
    "report says which: rest or the hanging equilibrium); slope of log dt_crit vs log k is -1/2 +- 0.05.", \
    "explicit_stability_map.png explicit_stability_ratio.png") \
  X(cb_check_E2, "E2", "explicit_stability", "Using a small dt makes explicit integration stable but slow.", \
    "Wall time to simulate 1 s: explicit at its largest stable dt against the fastest implicit method at dt = 1/30 " \
    "whose step error is within 1% (Baraff-Witkin counts), against k and resolution; a stretch- and a " \
    "bending-dominated family, each fitted exponent against the one its measured omega_max growth predicts (steps ~ " \
    "omega_max, work ~ n per step).", \
    "explicit_stability_cost.png") \
  X(cb_check_I1, "I1", "explicit_stability", \
    "Implicit Euler (converged Newton) stays stable for every (k, dt) in the same sweep; its price is numerical " \
    "damping.", \
    "Same sweep, over the same simulated time as the explicit cells: no divergence; energy lost per simulated second " \
    "as a function of dt.", \
    "explicit_stability_damping.png") \
  X(cb_check_newton_vs_bw_i2, "I2", "newton_vs_bw", \
    "Implicit Euler is x1 = argmin F(x), solved by Newton's method, which converges quadratically near the solution.", \
    "Measured convergence order from the |grad F| sequence is at least 1.8.", "newton_vs_bw_convergence.png") \
  X(cb_check_newton_vs_bw_i3, "I3", "newton_vs_bw", \
    "Baraff-Witkin's single Newton iteration is fast but can fail to converge.", \
    "Step error and wall time for K = 1, 2, 3, 5, 10 and converged; the (dt, k, stretch) regime where K = 1 has " \
    "error above 1% or diverges.", \
    "newton_vs_bw_pareto.png newton_vs_bw_regime.png newton_vs_bw_trajectory.png newton_vs_bw_energy.png") \
  X(cb_check_h1, "H1", "definiteness", \
    "A spring's Hessian is SPD when stretched and may be indefinite when compressed; A = M/dt^2 + H can then be " \
    "indefinite.", \
    "Fraction of Newton iterations with indefinite A on compression scenes.", "definiteness_h1.png") \
  X(cb_check_h2, "H2", "definiteness", \
    "Dropping the (1 - L/|x|) term when |x| < L restores definiteness; other fixes work at different costs.", \
    "Per fix: SPD rate, CG breakdowns, Newton iterations, wall time, final energy; each fix's Newton iterations, " \
    "factorisations and " \
    "wall time per step against drop's on the same scene (paired repeats), ranked; refuted by a fix that is not SPD " \
    "on some " \
    "iteration, and 'different costs' by every fix within 5% of drop's over the whole spread (a spread across the 5% " \
    "edge: undecided).", \
    "definiteness_residual.png definiteness_shapes.png") \
  X(cb_check_j1, "J1", "linear_solvers", \
    "Vanilla Jacobi needs A diagonally dominant; alpha < 2/lambda_max(D^-1 A) makes it converge for any SPD A.", \
    "alpha sweep on a non-diagonally-dominant SPD A: divergence at alpha = 1 where predicted, convergence for small " \
    "alpha, measured rate matches rho(I - alpha D^-1 A).", \
    "linear_solvers_j1_alpha.png linear_solvers_j1_rates.png") \
  X(cb_check_j2, "J2", "linear_solvers", \
    "Chebyshev acceleration makes Jacobi much faster (Wang 2015: at least an order of magnitude).", \
    "Iterations and wall time to relative residual 1e-6, Jacobi against Chebyshev-Jacobi on the same A.", \
    "linear_solvers_j2_speedup.png") \
  X(cb_check_nonlinear_j3, "J3", "nonlinear", \
    "Chebyshev needs an estimate of rho, and an overestimate diverges; the lab default 0.995 is reported to diverge " \
    "where about 0.95 works.", \
    "Two panels, rho swept 0.9 to 0.9999: (a) the lab's own nonlinear Chebyshev-Jacobi on F(x) (32 iterations a " \
    "frame, 2000 frames): divergence and its frame, median relative |grad F|, the true linearised rho; (b) linear " \
    "Chebyshev-Jacobi solves of captured Newton systems (linear_solvers): divergence boundary and the automatic " \
    "estimate.", \
    "nonlinear_j3_rho.png linear_solvers_j3_rho.png") \
  X(cb_check_w1, "W1", "nonlinear", \
    "Chebyshev accelerates the nonlinear iteration (Jacobi on F(x), projective dynamics) by at least an order of " \
    "magnitude (Wang 2015).", \
    "Iterations and wall time to relative |grad F| 1e-2 and 1e-4, jacobi-nl against chebyshev-nl and pd against " \
    "pd-chebyshev (rho = auto), at 21^2, 64^2 and 128^2; both sides run until they reach the tolerance (a run cut " \
    "off is rerun with a larger cap; a pair still cut off at the largest cap is undecided, never a failure); each " \
    "estimated rho against the plain iteration's rate.", \
    "nonlinear_w1.png") \
  X(cb_check_p1, "P1", "nonlinear", \
    "Projective dynamics reaches a visually converged step much faster than exact Newton (Liu et al. 2013: 50 ms " \
    "against 13 s per frame on a 6561-vertex cloth, 260x).", \
    "Wall time per frame and step error, pd (10 iterations) against the fastest Newton variant converged on every " \
    "frame (exact Hessian with line search, a non-SPD step rerun with drop and counted; or drop) and Baraff-Witkin, " \
    "on an 81^2 cloth and a stiff one; the time each needs to reach the same step error (1e-2, 1e-3); the ratio " \
    "against the paper's 260x.", \
    "nonlinear_p1.png nonlinear_error_time.png") \
  X(cb_check_j4, "J4", "linear_solvers", \
    "Direct solvers are one-shot, exact and expensive; iterative solvers are cheaper per iteration and their " \
    "accuracy is controllable.", \
    "Time to error 1e-6 against a manufactured solution (b = A x*, never against the direct solver) for CHOLMOD " \
    "(analyse + factor + " \
    "solve) and every iterative solver, on the lab cloth's Newton systems from 8^2 to 256^2: the crossover size from " \
    "which CHOLMOD " \
    "costs more than the best iterative solver, and each method's growth exponent in n (no crossover: \"expensive\" " \
    "not reproduced).", \
    "linear_solvers_j4_scaling.png linear_solvers_j4_error_time.png") \
  X(cb_check_B1, "B1", "bending", "A bending spring offers little resistance when the cloth is nearly planar.", \
    "Restoring force at the wing tip of one hinge against the fold angle 0-90 deg for spring, dihedral and " \
    "quadratic: " \
    "log-log slope over 1-10 deg >= 2.5 for the spring and within 1 +- 0.1 for both hinges.", \
    "bending_b1_force.png") \
  X(cb_check_B2, "B2", "bending", \
    "The quadratic bending model has a constant Hessian and makes simulation up to 3x faster than the nonlinear " \
    "hinge model.", \
    "Wall time per step under Newton with CHOLMOD on the sphere drape at two resolutions, quadratic against the " \
    "fastest dihedral " \
    "variant (its Gauss-Newton Hessian, PSD without per-element eigen-decomposition, or its exact projected one), " \
    "with the " \
    "assembly/factorisation/solve split and Newton iterations; the rest shapes' RMS distance. Reproduced for a " \
    "speed-up of " \
    "1.5-4.5x; above 4.5x or 1.1-1.5x partly; at or below 1.1x not.", \
    "bending_b2_rest.png") \
  X(cb_check_B3, "B3", "bending", "The quadratic bending model is no longer valid if cloth stretches much.", \
    "Quadratic against hinge energy on a folded mesh where their ratio is no closed-form identity: a strip with " \
    "unequal hinge " \
    "wings (jittered vertices) bent onto a cylinder, stretched in-plane by a non-uniform field (strain ramping along " \
    "the strip " \
    "to a peak of 0-30%, along the arc or along the axis): the peak stretch at which they differ by more than 10%, " \
    "and their " \
    "unstretched agreement (reproduced if they agree within 10% unstretched and part within 30%, in every stretch " \
    "field).", \
    "bending_b3_stretch.png") \
  X(cb_check_L1, "L1", "locking", "Locking: stiff in-plane edges resist folding even with zero bending stiffness.", \
    "Fold angle at rest under gravity, bending stiffness 0, against in-plane stiffness (1e1-1e7), for fold lines " \
    "along mesh edges, along and across the diagonals and at an angle no mesh line follows; regular, alternating and " \
    "unstructured meshes; springs and co-rotational FEM. Along mesh edges the angle must stay within 5 deg of the " \
    "free fold's (the flap hangs straight); across mesh lines it must fall with k at every step, not only from the " \
    "first to the last.", \
    "locking_l1.png") \
  X(cb_check_L2, "L2", "locking", \
    "Nonconforming (edge-midpoint) elements (English & Bridson 2008) keep about 3 DoFs per vertex where conforming " \
    "meshes keep 3 + #boundary_edges in all.", \
    "3 #variables - rank of the rigidity matrix, per vertex, against mesh size, both discretisations.", \
    "locking_l2.png") \
  X(cb_check_F1, "F1", "locking", \
    "Co-rotational FEM can replace planar springs (lecture summary): it is isotropic where a spring network depends " \
    "on its mesh, and its frozen-rotation Hessian is constant.", \
    "Anisotropy of the response to non-affine loads (affine loads pass the patch test by construction and decide " \
    "nothing): disks with the boundary held at a non-uniform stretch or an in-plane bending shear in 8 directions, " \
    "springs against FEM on the regular, alternating and unstructured meshes, compared across meshes and across " \
    "directions; one Newton step at 64^2 as error against time, FEM frozen/exact against springs, with every run's " \
    "convergence status.", \
    "locking_f1_aniso.png locking_f1_newton.png") \
  X(cb_check_S1, "S1", "locking", \
    "Shape matching (Mueller 2005) is unconditionally stable under explicit integration.", \
    "alpha in [0.01, 1] x explicit_stability's dt range: a cell is stable only if its energy and its shape error " \
    "(largest edge strain against the rest shape, and the distance to the best-fit rigid motion) both stay bounded; " \
    "unstable cells count against the claim. Against springs under the same integrator.", \
    "locking_s1.png") \
  X(cb_check_X1, "X1", "field", \
    "XPBD (Macklin et al. 2016) makes the converged stiffness independent of the iteration count and dt; PBD's " \
    "depends on both.", \
    "Effective stiffness (static stretch of a hanging strip and of the lab cloth under gravity, against the spring's " \
    "k) at the iteration count where XPBD's constraint residual has converged, for 3 values of dt, PBD against XPBD: " \
    "its spread over dt (and its approach over 1-100 iterations, shown).", \
    "field_x1.png") \
  X(cb_check_X2, "X2", "field", \
    "Small steps (Macklin et al. 2019): at equal work, n substeps of one iteration beat one step of n iterations, " \
    "with far less stretching.", \
    "For n = 1-64: distance of the largest edge stretch from the converged implicit step's, blow-ups, error against " \
    "that step at the frame ends, and wall time per frame, XPBD n x 1 against 1 x n, on the lab cloth and a stiff " \
    "cloth.", \
    "field_x2.png") \
  X(cb_check_Q1, "Q1", "field", \
    "Quasi-Newton (Liu et al. 2017): L-BFGS with PD's constant matrix as its initial Hessian and a line search " \
    "converges faster in wall time than PD and than Newton (about 10x over Newton: 20.1 against 308 ms a frame).", \
    "Wall time to relative |grad F| 1e-3 and 1e-5 per frame, L-BFGS (window 5) against PD, Chebyshev-PD and the " \
    "fastest Newton variant, on 81^2, its stiff variant and the drape; error against time curves.", \
    "field_q1.png field.png") \
  X(cb_check_V1, "V1", "field", \
    "Vertex block descent (Chen et al. 2024) lowers the implicit-Euler objective at every iteration, stays stable " \
    "from any initial state, and converges faster than Jacobi-type iterations.", \
    "Over every step of every scene: objective rises counted; a scrambled start (vertices displaced at random by up " \
    "to the cloth's size) recovers without divergence (its excess strain decays); |grad F| against iterations and " \
    "wall time, VBD and vbd-chebyshev against jacobi-nl, chebyshev-nl and pd-chebyshev.", \
    "field_v1.png field.png") \
  X(cb_check_C1, "C1", "contact", \
    "Incremental potential contact (Li et al. 2020; codimensional, Li, Kaufman & Jiang 2021) keeps cloth " \
    "intersection-free at every step, for any dt and speed, where a penalty without continuous collision detection " \
    "tunnels.", \
    "Over a sweep of dt and drop speed on the sheet falling onto a table (folding over itself) and the cloth on a " \
    "rotating sphere: the exact count of intersecting non-adjacent triangle pairs at every frame, the smallest " \
    "separation and the contact count, for every registered response (ipc and penalty under Newton today). " \
    "Reproduced if IPC has 0 intersections at every frame of every cell and the penalty has some; the contrast not " \
    "shown (penalty never tunnels) is partly.", \
    "contact.png") \
  X(cb_check_C2, "C2", "contact", \
    "Lagged, smoothed Coulomb friction (Li et al. 2020) reproduces Coulomb's stick-slip threshold: cloth on a slope " \
    "of angle theta stays put when mu > tan theta and slides when mu < tan theta.", \
    "Sliding distance after 1 s against mu for several theta, for ipc and VBD's contact; the measured threshold mu* " \
    "against tan theta (within 10%), and the creep below it (slide at mu = 1.5 tan theta, against eps_v).", \
    "contact_c2.png") \
  X(cb_check_C3, "C3", "contact", \
    "Vertex block descent with per-vertex contact bounds (Chen et al. 2024) reaches a given accuracy on contact-rich " \
    "scenes faster than IPC's Newton, and stays free of intersections.", \
    "One step from the same contact-rich state (frames of ipc under Newton) on the rotating sphere and the " \
    "self-folding sheet, by VBD with contact (sweeps 1, 2, 4, ...), IPC's Newton (iterations 1..32) and L-BFGS with " \
    "the barrier (1..64): step error against IPC's converged step against wall time (median of interleaved " \
    "repeats), at errors 1e-2 and 1e-3, and the exact intersection count of every result. Reproduced if VBD reaches " \
    "both errors faster than Newton (the paired spread of the ratio below 1) on both scenes with no intersection; " \
    "not reproduced if it intersects or wins no comparison; partly if it wins some.", \
    "contact_c3.png") \
  /* one X(...) entry per claim, above this line */

#endif
