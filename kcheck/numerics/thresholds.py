"""Every numerical threshold of kcheck and its built-in checks, in one place.

A threshold here is a number a computation compares against to decide something that exact
arithmetic would decide without it: a rank, a singular or ill-conditioned matrix, whether a
root is real, two points, caps or roots are the same, a contact slides, a point lies on a
boundary, an iteration has converged. Each constant says (in its ``#:`` comment) what it
bounds, in which units or that it is nondimensional, and why it has its value. Most are
relative to a scale named in the comment, or act on kcheck's nondimensional quantities
(positions in layout lengths ``L``, forces in the load scale, unit twists and directions:
:mod:`kcheck.mechanics.kinematics`), so they do not depend on mm versus m.

Not here: unit conversions (:mod:`kcheck.scene.units`), the physical ranges the scene accepts
(:mod:`kcheck.scene.limits`), design rules and plausibility warnings (check options,
:mod:`kcheck.analysis.sanity`), iteration counts and grid sizes, and the cosmetics of
pictures. Constants that mean different things keep different names even where their values
agree; where two decisions of the same kind use different values, both comments say why.

The numerics layer is the lowest: this module imports nothing from kcheck, and not numpy
either (``sys.float_info`` gives the same machine constants as ``np.finfo(float)``), so any
module may use it without an import cost.
"""

from __future__ import annotations

import math
import sys

__all__ = [
    "MARGIN_SCREEN_DEG",
    "FORCE_SCREEN_RTOL",
    "FORCE_SCREEN_ROUNDINGS",
    "THERMAL_CENTRE_DET",
    "EPS",
    "DET_ROUNDING",
    "TINY",
    "ZERO_GUARD",
    "LENTZ_RTOL",
    "QUANTILE_ATOL",
    "NOISE_RTOL",
    "RANK_RTOL",
    "UNDETERMINED",
    "TILTED_UNDETERMINED",
    "NEARLY_SINGULAR",
    "ILL_CONDITIONED",
    "PENCIL_SINGULAR",
    "PENCIL_UNSHIFTED",
    "HOLDING_CERTIFICATE_MARGIN",
    "HOLDING_CERTIFICATE_CONDITION",
    "HOLDING_CERTIFICATE_STEPS",
    "HOLDING_CERTIFICATE_BATCH",
    "SLIP_TOL",
    "INFINITE_POLE",
    "NO_PITCH",
    "PLANAR_TOL",
    "IN_SWEEP_PLANE",
    "PARALLEL_COS",
    "PARALLEL_SIN",
    "PLANE_BASIS_SIN",
    "ROTATION_TOL",
    "PRINCIPAL_TRIANGLE_RTOL",
    "CACHED_SYMMETRY_RTOL",
    "MERGE_RTOL",
    "DEGENERATE_FACE_RTOL",
    "NO_VOLUME_RTOL",
    "SAME_POINT_RTOL",
    "POLISH_XTOL",
    "POLISH_FTOL",
    "FACET_TOL",
    "HULL_FACET_TOL",
    "IMAGE_RANK_RTOL",
    "RANK_MINOR_MARGIN",
    "PRODUCT_ROUNDING",
    "FACET_DECIMALS",
    "HULL_FACET_DECIMALS",
    "EDGE_WRENCH_DECIMALS",
    "SAME_FACET",
    "WELL_INSIDE",
    "LP_POSITIVE",
    "LP_EQUALITY_SLACK",
    "ARC_ZERO_RTOL",
    "SLIVER",
    "FREE_CANDIDATE_TOL",
    "FULL_TURN_SLACK_DEG",
    "NO_SAFE_DIRECTION_SLACK",
    "UNCERTAIN_DEG",
    "ENVELOPE_TOL",
    "ENVELOPE_INSIDE_SLACK",
    "SAMPLE_STEP_FLOOR",
    "SAME_CAP",
    "ON_BOUNDARY",
    "AXIS_FOOT",
    "ATAN_SERIES",
    "ON_UNIT_SPHERE",
    "ARCCOS_ANGLE_SLACK",
    "QUADRATIC_LEAD",
    "DEGREE_RTOL",
    "IMAG_TOL",
    "ROOT_SLACK_RTOL",
    "ENVELOPE_IMAG_TOL",
    "IMAG_RTOL",
    "PENCIL_INFINITE_RTOL",
    "SAME_ROOT_RTOL",
    "MU_END_RTOL",
    "SAME_FRICTION_RTOL",
    "POLY_ZERO_RTOL",
    "CUBIC_IMAG_RTOL",
    "MU_FLOOR",
    "MU_RTOL",
    "JAM_MU_RTOL",
    "DINKELBACH_STALL",
    "PRESSED_RTOL",
    "FRICTIONLESS_MISS",
    "NEWTON_RTOL",
    "LIFT_RTOL",
    "SLIDING_CERTIFICATE_MARGIN",
    "SLIDING_NEWTON_DIVERGED",
    "BALANCE_RTOL",
    "OUTSIDE_PYRAMIDS",
    "GOLDEN_XTOL",
    "LEAST_FORCE_RTOL",
    "CURVATURE_RTOL",
    "AGM_ULP_FRACTION",
    "LIFTED_RTOL",
    "RESEAT_WINDOW_SHARE",
    "RESEAT_JAM_FACTOR",
    "RESEAT_RELEASE_TIME_CONSTANTS",
    "RESEAT_BACKOFF_SHARE",
    "RESEAT_BACKOFF_MOTION_SHARE",
    "RESEAT_LOST_SHARE",
    "RESEAT_STICK_SHARE",
    "RESEAT_ESTIMATE_FACTOR",
    "RESEAT_SEAT_RESOLUTION",
    "RESEAT_REST_SPEED",
    "LEMKE_PIVOT_RTOL",
    "LIFT_SHARE",
    "CONTACT_GAP_RTOL",
    "SMOOTH_PATCH_DEG",
    "SURFACE_FIT_RTOL",
    "EXTRUSION_DEG",
]

# --- floating point ----------------------------------------------------------------------

#: Machine epsilon of a double, 2**-52 (nondimensional): the spacing of floats at 1 and the
#: unit of every rounding-error estimate (``k * EPS * size``); ``np.finfo(float).eps``.
EPS: float = sys.float_info.epsilon
#: The smallest positive normal double, 2**-1022 (any unit): a scale at or below it is left
#: unscaled by equilibration, because its reciprocal would overflow; ``np.finfo(float).tiny``.
TINY: float = sys.float_info.min
#: A positive stand-in for a zero scale or divisor (any unit): taken as the floor of a scale
#: before dividing by it or multiplying a tolerance by it, so a zero scale gives a zero ratio or
#: an exact-zero test instead of NaN; the modified Lentz continued fraction puts it in place
#: of a zero denominator (Numerical Recipes' FPMIN). Far below any scale the scene limits admit
#: (kcheck.scene.limits) and a normal float (above TINY), so its reciprocal, 1e300, is finite.
ZERO_GUARD: float = 1e-300
#: Convergence of the incomplete beta function's continued fraction (nondimensional): stop
#: when a step changes the value by a factor within this of 1, a few roundings (5 EPS).
LENTZ_RTOL: float = 1e-15
#: Bisection of a beta quantile stops when its bracket is narrower than this (a probability,
#: nondimensional): far below the digits a confidence bound is reported with, and above the
#: rounding of the incomplete beta function (about 1e-15).
QUANTILE_ATOL: float = 1e-13
#: An entry below this fraction of the largest (or of the scale given) is rounding noise and
#: written as 0 (nondimensional): about 5e6 roundings, above the error of well-conditioned
#: solves and far below the 3 to 6 significant digits a report shows.
NOISE_RTOL: float = 1e-9

# --- rank, determinacy and conditioning ------------------------------------------------------

#: Singular values below this fraction of the largest count as zero (rank decisions of the
#: constraint rows, nondimensional: rows in layout lengths). About 5e5 roundings: a layout
#: exact to 10 digits is still of full rank, one degenerate to rounding is not.
RANK_RTOL: float = 1e-10
#: A free twist is not unique (the case is ``undetermined``) when its determinacy (smallest
#: over largest singular value of the remaining rows) is at or below this, and it does not
#: close the retracted support when its closing rate ``-n_r . u(p_r)`` is (both nondimensional:
#: unit twists, layout lengths). The same cut as RANK_RTOL, applied per retracted support.
UNDETERMINED: float = 1e-10
#: Koster's construction: the friction-tilted reaction lines of the two kept supports are
#: parallel (no friction pole) when the sine of the angle between their rows, ``|a x b| /
#: |a||b|``, is at or below this (nondimensional). A cross product of two rows is accurate to
#: their rounding, about 1e-16, so the cut is tighter than UNDETERMINED's, which judges
#: singular values from an SVD of several rows.
TILTED_UNDETERMINED: float = 1e-12
#: A deterministic layout whose smallest scaled singular value (over the largest) is below
#: this is called nearly singular in the maxwell check's message (nondimensional): its free
#: motions and forces then amplify errors of the input by a million or more.
NEARLY_SINGULAR: float = 1e-6
#: Condition number (of an equilibrated system, nondimensional) above which its solution is
#: not trusted: the case is reported ``ill_conditioned`` without numbers, a stiffness matrix is
#: not inverted, a range is not decided from it. At 1e12 the forward error, condition * EPS,
#: reaches about 2e-4 relative, just below the three significant digits a report shows.
ILL_CONDITIONED: float = 1e12
#: A friction pencil whose every shifted matrix is worse conditioned than this is singular for
#: every mu (nondimensional): the same bound as ILL_CONDITIONED, applied to the best of the
#: shifts.
PENCIL_SINGULAR: float = 1e12
#: A friction pencil whose unshifted matrix has a Hadamard ratio (|det| over the product of
#: its rows' norms, 1 for orthogonal rows; nondimensional) at least this is solved
#: unshifted, without trying the other shifts: its roots then move by rounding only (on
#: 1000 generated scenes by at most 2.4e-14 relative, far inside their error bounds; the
#: best ratio's median over the shifts is 0.40, the unshifted one's 0.35).
PENCIL_UNSHIFTED: float = 0.05

# --- kinematics and dynamics ----------------------------------------------------------------

#: A contact whose nondimensional speed under the unit free twist is at or below this does not
#: slide: its friction direction is undetermined and, as in the thesis, its friction is set to
#: zero. Speeds are in layout lengths per unit twist; 1e-9 is far above the rounding of the
#: SVD that gives the twist (about 1e-15) and far below any sliding that matters.
SLIP_TOL: float = 1e-9
#: A rotation whose pole lies beyond 1e12 layout sizes (``|w| <= INFINITE_POLE |v|``,
#: nondimensional) is reported as a translation: a pole that far is rounding of a zero ``w``.
INFINITE_POLE: float = 1e-12
#: A screw whose pitch is at or below this (layout lengths per radian, nondimensional) is
#: reported as a pure rotation: the pitch of a pure rotation computed in floats is rounding,
#: about 1e-16.
NO_PITCH: float = 1e-9
#: A trial scene of a way-out search is rejected before its sphere map when the design
#: direction's margin in closed form (the least over the closing caps) lies this far (deg)
#: below the margin the check asks for; the map's own margin agrees to about 1e-12 rad, so
#: the band only keeps a tie for the map to decide.
MARGIN_SCREEN_DEG: float = 1e-6
#: A way-out trial closing force is rejected in closed form only where a closing condition is
#: negative by more than this share of its case's solution size (nondimensional; or by
#: FORCE_SCREEN_ROUNDINGS times its system's rounding, condition number times eps, when that
#: is larger): near a sign change the trial is judged in full.
FORCE_SCREEN_RTOL: float = 1e-6
#: How many times its system's rounding (condition number times eps) a closing condition must
#: be negative by before the closed-form screen rejects a trial force (nondimensional; see
#: FORCE_SCREEN_RTOL): a wide margin over the rounding a solve can carry.
FORCE_SCREEN_ROUNDINGS: float = 1e3

# --- directions, planes and same points ----------------------------------------------------

#: "Lies in the plane" for a planar scene (nondimensional): the z-component of a unit normal,
#: and the spread of the support heights over the layout size, at most this. Ten digits: a
#: scene typed or exported with them counts as planar, one visibly tilted does not.
PLANAR_TOL: float = 1e-9
#: The design direction lies in the sweep plane (nondimensional, unit vectors) when its
#: component along the plane's normal, or the in-plane part's departure from unit length, is
#: below this: rounding of a direction built in the plane is about 1e-16. Equal to PLANAR_TOL
#: but a different decision (whether to report the design's angle, not whether to accept a
#: scene).
IN_SWEEP_PLANE: float = 1e-9
#: Two unit directions are parallel when ``|cos|`` of their angle exceeds this
#: (nondimensional; an angle below about 4.5e-5 rad): a coupling's ``up`` and a groove or flat
#: then define no perpendicular worth building a contact on.
PARALLEL_COS: float = 1 - 1e-9
#: A direction is parallel to a unit normal when its part perpendicular to the normal is
#: shorter than this (nondimensional, unit directions): then no tangent or sweep axis can be
#: built from it. Ten digits, like PLANAR_TOL; PARALLEL_COS, a bound on the cosine, accepts
#: less (its angle is 4.5e-5 rad, this one's 1e-9 rad).
PARALLEL_SIN: float = 1e-9
#: A candidate axis for the second vector of a sweep plane is used only when its part
#: perpendicular to the first is longer than this (nondimensional, unit vectors), else the
#: next candidate: a basis built from a shorter part would carry its rounding into every
#: angle. Larger than PARALLEL_SIN because a fallback exists here; nothing is refused.
PLANE_BASIS_SIN: float = 1e-6
#: A rotation matrix typed in a scene may have entries up to 1 plus this and ``R^T R`` may
#: differ from the identity by this much (nondimensional) before it is refused; it is then
#: orthonormalised. Six to seven digits, what a matrix copied from CAD usually has.
ROTATION_TOL: float = 1e-6
#: Principal moments of inertia must satisfy the triangle inequality ``a + b >= c`` to this
#: relative slack (nondimensional): a thin plate or rod meets it with equality, and its moments
#: typed with six to seven digits may miss it by rounding.
PRINCIPAL_TRIANGLE_RTOL: float = 1e-6
#: A cached inertia tensor must be symmetric to this (relative, nondimensional): the cache
#: stores what kcheck computed (symmetric to rounding), so anything worse is a damaged entry.
#: Tighter than kcheck.scene.limits.INERTIA_SYMMETRY_RTOL (1e-6), which is for typed input.
CACHED_SYMMETRY_RTOL: float = 1e-9
#: Mesh vertices closer than this fraction of the mesh's largest extent are one vertex
#: (nondimensional): STL files repeat a vertex per triangle, in float32 (about 7 digits).
MERGE_RTOL: float = 1e-6
#: A mesh face whose area is at most ``(DEGENERATE_FACE_RTOL * extent) ** 2`` is degenerate
#: (nondimensional; extent: the mesh's largest extent): far below what float32 coordinates
#: (STL, 1e-7 of the extent) resolve, so only a face collapsed to a line or a point.
DEGENERATE_FACE_RTOL: float = 1e-12
#: A mesh enclosing at most ``(NO_VOLUME_RTOL * extent) ** 3`` encloses no volume
#: (nondimensional): the volume of a flat or open surface computed in floats is rounding.
NO_VOLUME_RTOL: float = 1e-9
#: Candidate points (kcheck suggest) closer than this fraction of the candidates' span are the
#: same point found twice (nondimensional): the same candidate reached twice agrees to
#: rounding.
SAME_POINT_RTOL: float = 1e-9

#: The continuous search over the attachment point (kcheck suggest) stops when its simplex is
#: this fraction of the sampling step (nondimensional; a 5 mm step: 5 µm) ...
POLISH_XTOL: float = 1e-3

#: ... and its margins agree to this (rad) (1e-5 rad is 6e-4°): two orders below the 0.05°
#: the search promises against an exhaustive reference (docs/suggest.md).
POLISH_FTOL: float = 1e-5

# --- cones and linear programmes ---------------------------------------------------------------

#: Relative tolerance of "generator on the facet's plane" and of facets through the origin in
#: wrench cones (nondimensional: unit facet normals, generators in layout units); with
#: exact cross products (three dimensions) rounding is about 1e-15.
FACET_TOL: float = 1e-10
#: FACET_TOL for facets from qhull (four or more dimensions; nondimensional): its joggled input
#: (``QJ``) moves facets by about 1e-11 and the section adds rounding, so a thousand times
#: looser.
HULL_FACET_TOL: float = 1e3 * FACET_TOL
#: An image's columns (nondimensional, relative to its largest QR entry) are of full rank when
#: each diagonal entry of R exceeds this share (cones.balanced_image): the same rounding
#: (about 1e-15) and margin as FACET_TOL, whose value it takes.
IMAGE_RANK_RTOL: float = FACET_TOL
#: A planar cone's rank is 3 without its singular values when three generators' determinant
#: bounds the least singular value above this many times FACET_TOL (nondimensional; the rank
#: test's own threshold; rounding of either is about 1e-15, so the SVD's count would be 3 as
#: well).
RANK_MINOR_MARGIN: float = 100.0
#: Roundings (EPS each, relative to the wrench's size: nondimensional) by which a unit
#: facet's product with a wrench may differ between numpy (its matrix product fuses
#: multiply-adds) and plain float arithmetic: about 6 at most for three terms. A planar cone
#: decision in plain arithmetic stands only where every product is farther than this from
#: its limit (:func:`kcheck.mechanics.statics.planar_holding`); otherwise numpy decides.
PRODUCT_ROUNDING: float = 64.0
#: Facet normals (unit, nondimensional) equal to this many decimals are one facet: exact
#: cross products (three dimensions) agree to about 1e-15.
FACET_DECIMALS: int = 13
#: FACET_DECIMALS for qhull's facets (unit normals, nondimensional), which its joggle moves by
#: about 1e-11 (1e-9: two digits of margin).
HULL_FACET_DECIMALS: int = 9
#: Unit edge wrenches of friction cones (nondimensional) equal to this many decimals are one
#: generator (a frictionless contact's coinciding edges, supports at one point): computed
#: row by row from the same numbers they agree to about 1e-16, distinct edges differ by far
#: more.
EDGE_WRENCH_DECIMALS: int = 14
#: A cone facet is the sweep plane's own (Koster's construction) when the cosine between
#: their unit normals exceeds ``1 - SAME_FACET`` (nondimensional): the same plane computed two
#: ways agrees to rounding, a different facet differs by far more.
SAME_FACET: float = 1e-11
#: Perceptron steps stop at a direction inside a cone by at least this cosine margin
#: (nondimensional, unit generators): a direction barely inside makes a badly scaled section
#: for qhull, so a smaller margin goes on to the linear programme.
WELL_INSIDE: float = 0.05
#: A linear programme's variable (scaled to at most 1: a cone's margin, a generator's share in
#: a positive dependency) counts as positive above this (nondimensional): clarabel's default
#: tolerances are about 1e-8, so smaller values are within the solver's error.
LP_POSITIVE: float = 1e-6
#: Slack of the equalities ``G^T lambda = 0`` written as two inequalities in the lineality
#: programme (nondimensional, unit generators): a little slack leaves the interior-point
#: solver an interior; with ``lambda <= 1e6`` it admits only dependencies that hold to about
#: 1e-15 relative, i.e. to rounding.
LP_EQUALITY_SLACK: float = 1e-9

# --- arcs and angles -------------------------------------------------------------------------

#: A direction term of a condition ``a + b cos + s sin > 0`` below this fraction of the
#: condition's own size is no term (nondimensional): 64 roundings of that size, so a
#: coefficient that is zero in exact arithmetic is zero here; per condition, so a huge unknown
#: does not erase a small one's direction term.
ARC_ZERO_RTOL: float = 64 * EPS
#: Arcs shorter than this (rad) are rounding slivers between sets that share an end; gaps
#: shorter than it are joins (the same end computed through a different wrap of 2 pi, about
#: 1e-15 rad apart).
SLIVER: float = 1e-12
#: A range of directions this close to 360 degrees (deg) is the full turn, both when it is
#: formatted and when it is worded: ends computed through a wrap of 360 differ by about 1e-13.
FULL_TURN_SLACK_DEG: float = 1e-9
#: A robustness margin within this of -pi (rad) means no direction is safe at that point
#: (kcheck suggest's report): margins with no safe direction are set to -pi exactly; the
#: slack absorbs rounding of margins computed next to it.
NO_SAFE_DIRECTION_SLACK: float = 1e-9
#: Range ends less certain than this (deg) are reported with a diagnostic: reports show angles
#: to two decimals.
UNCERTAIN_DEG: float = 0.01
#: Angular error (rad) aimed at where an envelope of caps is approximated by caps at sampled
#: coefficients: the 0.01 degree a report shows (as UNCERTAIN_DEG).
ENVELOPE_TOL: float = math.radians(0.01)
#: An envelope point counts as inside the caps of a range's ends when every condition there is
#: above minus this (nondimensional condition values): boundary slack for the rounding of
#: points that lie on an end circle.
ENVELOPE_INSIDE_SLACK: float = 1e-12
#: Floor of the sampling step along a friction range (nondimensional path parameter in
#: [-1, 1]): keeps a zero wanted step from dividing by zero; such a step then asks for the
#: most samples.
SAMPLE_STEP_FLOOR: float = 1e-12
#: Caps whose axes (unit vectors) and cosines of radii agree to this (nondimensional) are one
#: cap (duplicates would count twice); it is also the slack of the test whether two caps are
#: disjoint (the cosine between their axes against ``cos(r_i + r_j)``, and ``r_i + r_j`` (rad)
#: against pi). Caps of conditions computed two ways agree to rounding, about 1e-15.
SAME_CAP: float = 1e-12
#: A candidate point counts as inside a cap when its margin is above minus this (rad), and a
#: cap is nearer than the active set's when it is by more: points on a cap's circle are
#: computed to about 1e-15 rad.
ON_BOUNDARY: float = 1e-11
#: Most an angle (rad) between two unit vectors taken as ``arccos`` of their dot product can
#: differ from the accurate ``atan2`` form: ``sqrt(2 eps)`` ~ 1.5e-8 near 0 and pi, where
#: arccos is steepest (its rounding alone: a pre-selection, never a margin reported).
ARCCOS_ANGLE_SLACK: float = 1e-7
#: A direction whose part perpendicular to a cap's axis is at most this (unit vectors,
#: nondimensional) lies on the axis: every point of the circle is then a foot of the
#: perpendicular, and one is taken. A perpendicular part that short is rounding of zero.
AXIS_FOOT: float = 1e-15
#: ``atan(y) / y`` is taken as its series ``1 - y^2 / 3`` below this ``|y|`` (nondimensional):
#: there the next term, ``y^4 / 5``, is below 1e-32, far below rounding, and 0/0 is avoided.
ATAN_SERIES: float = 1e-8
#: A candidate for the deepest point of caps must have unit length to this (nondimensional):
#: points built from a solved quadratic lie on the sphere to rounding; a wrong root does not.
ON_UNIT_SPHERE: float = 1e-6
#: The quadratic in ``tan t`` for points equidistant from three circles is taken as linear
#: when its leading coefficient is at most this (nondimensional, unit axes): then the
#: quadratic formula loses all digits.
QUADRATIC_LEAD: float = 1e-14

# --- polynomials and roots ---------------------------------------------------------------------

#: A Chebyshev coefficient below this fraction of the largest counts as zero (the degree
#: drops; nondimensional): a leading coefficient that is rounding of zero would make huge
#: spurious roots.
DEGREE_RTOL: float = 1e-12
#: Eigenvalues of a Chebyshev companion matrix with an imaginary part below this (relative to
#: ``1 + |real part|``) are real roots (nondimensional): a spare root costs one evaluation, a
#: missed one would merge two pieces.
IMAG_TOL: float = 1e-7
#: Real roots this far (relative to the interval's length) outside the interval are clipped
#: into it (nondimensional): a root at an end moves by rounding when it is polished.
ROOT_SLACK_RTOL: float = 1e-12
#: IMAG_TOL for the envelope polynomials of friction ranges (nondimensional, relative to
#: ``1 + |real part|``): their double roots (both ends of a half circle turning back together)
#: split by rounding into complex pairs, by about the square root of the rounding of a product
#: of series, so a looser bound keeps them (a spare candidate costs one decision).
ENVELOPE_IMAG_TOL: float = 1e-5
#: IMAG_TOL for the eigenvalues of friction pencils (nondimensional, relative to
#: ``1 + |real part|``): a spare breakpoint costs one evaluation, a missed one would merge two
#: pieces.
IMAG_RTOL: float = 1e-6
#: A pencil eigenvalue below this fraction of the largest is zero: its root in mu lies at
#: infinity (nondimensional; about 50 roundings).
PENCIL_INFINITE_RTOL: float = 1e-14
#: Breakpoints in mu closer than this (relative) are one (nondimensional): the same root found
#: from two shifts agrees to rounding.
SAME_ROOT_RTOL: float = 1e-13
#: A friction coefficient within this of an interval's end (relative to ``max(1, mu)``,
#: nondimensional) lies in the interval: the ends are roots computed to about 1e-15, so the
#: scene's own coefficient at an end is not lost to their rounding.
MU_END_RTOL: float = 1e-9
#: Friction coefficients that agree to this (relative to the largest) are one uniform
#: coefficient (nondimensional): the same number typed twice, or converted, agrees to rounding.
SAME_FRICTION_RTOL: float = 1e-12
#: A coefficient of a polynomial in mu (degree up to three) below this fraction of the sum of
#: its magnitudes is zero (nondimensional): about 50 roundings, tighter than
#: DEGREE_RTOL because these come from a few products of unit rows, not from interpolation.
POLY_ZERO_RTOL: float = 1e-14
#: Roots of those polynomials with an imaginary part below this (relative to ``max(|root|, 1)``)
#: are real (nondimensional): Newton steps polish the kept roots afterwards and each is then
#: tested for feasibility, so a spurious candidate costs one test.
CUBIC_IMAG_RTOL: float = 1e-9

# --- convergence of searches -------------------------------------------------------------------

#: Friction coefficients below this are zero to every purpose: a bisection for the least
#: holding coefficient stops there (nondimensional); relative steps alone would halve into
#: denormals and then loop forever at 5e-324.
MU_FLOOR: float = 1e-12
#: Default relative accuracy of the least holding friction coefficient (nondimensional): far
#: finer than the three significant digits a report shows.
MU_RTOL: float = 1e-6
#: The jamming check's relative accuracy of the least holding coefficient (nondimensional):
#: coarser than MU_RTOL because its messages show three significant digits and each step in
#: space is a conic solve.
JAM_MU_RTOL: float = 1e-4
#: A Dinkelbach-type step that lowers the friction ratio by less than this multiple of the
#: wanted accuracy (``rtol * ratio``) ends the steps (nondimensional). They converge
#: quadratically: the next relative error is about ``C gain^2`` with ``C`` 3 (median), 14
#: (90th percentile), 127 (largest) over 315 steps on the fixtures and generated scenes. So
#: after a gain of ``10 rtol`` (1e-3 at the jamming check's 1e-4) the error left is mostly
#: a few 1e-6, far inside ``rtol``; where it is not, the check at ``(1 - rtol)`` times the
#: result finds it and the steps go on from there.
DINKELBACH_STALL: float = 10.0
#: A contact whose normal force is at or below this fraction of the largest normal force is
#: not pressed and takes no part in the friction ratio (nondimensional): it is below the conic
#: solver's tolerances (about 1e-8), so its ratio would be noise.
PRESSED_RTOL: float = 1e-9
#: A wrench that normal forces of any sign miss by more than this fraction of its size
#: (least squares, nondimensional) cannot be held without friction: the least holding
#: friction skips the conic solve at coefficient 0, whose answer is then certain (the
#: solver's feasibility tolerances are 1e-8, its reduced ones 1e-4, far below).
FRICTIONLESS_MISS: float = 1e-2
#: The sliding limit's Newton steps (least holding friction in space) end when a step moves
#: ``mu`` by less than this (relative) and the twist (about unit size) by less than it
#: (nondimensional): they converge quadratically, so the result is then near rounding (its
#: certificate checks it, to the caller's ``rtol``).
NEWTON_RTOL: float = 1e-7
#: A Newton step of the sliding limit that moves ``mu`` by less than this (relative,
#: nondimensional) decides which contacts lift off: those whose force is below ``-LIFT_RTOL``
#: times the largest (far beyond the square of the step, the error left).
LIFT_RTOL: float = 1e-3
#: The least margin (relative to the terms compared, nondimensional) by which the sliding
#: limit's separating twist must clear every friction cone at ``(1 - rtol)`` times the
#: result: far above the rounding of the few products it is computed from (about 1e-16).
SLIDING_CERTIFICATE_MARGIN: float = 1e-9
#: The sliding limit's Newton steps have diverged once ``|mu|`` or a component of the twist
#: (scaled to about 1 by ``start . h = 1``; nondimensional) passes this: a limit above the
#: search's ``largest`` coefficient, 100, is none the caller wants.
SLIDING_NEWTON_DIVERGED: float = 1e3
#: The largest imbalance (relative to the wrench, nondimensional) of the sliding limit's
#: forces: a converged Newton solve leaves about 1e-15; the conic solver's own tolerance is
#: 1e-8. Its "holds" side is certified to this, not exactly (as the conic search is to its
#: tolerance).
BALANCE_RTOL: float = 1e-10
#: A design direction outside a facet of the circumscribed pyramids' held set by more than
#: this slack (``a + c . d``, unit facet normals against the nondimensional wrench) is held
#: by no circular cone inside them: the jamming check skips the conic solve there. Far above
#: the facets' rounding (9 decimals, qhull's joggle about 1e-11) and the solver's reduced
#: feasibility tolerance (1e-4), so the solver could not have answered otherwise.
OUTSIDE_PYRAMIDS: float = 1e-2
#: Golden-section search along a friction range stops when its bracket is narrower than this
#: (nondimensional path parameter in [-1, 1]): a few thousand roundings of the parameter, far
#: below any change of the margin a report shows.
GOLDEN_XTOL: float = 1e-12
#: kcheck suggest's least closing load is bisected to this relative accuracy (nondimensional):
#: an answer for a designer, and each step searches every candidate point.
LEAST_FORCE_RTOL: float = 0.01

#: A lattice direction inside a held set of the jamming map by more than this (nondimensional,
#: the facet's ``a + c . d`` with unit-scale coefficients) is left out of the search for the
#: freest direction (which lies outside every held set); far above rounding (1e-16), so no
#: direction outside is left out.
FREE_CANDIDATE_TOL: float = 1e-9
#: Constant of the determinant's rounding bound (:func:`kcheck.mechanics.friction_range.
#: determinant_error`, nondimensional): LU's backward error is ``γ |K|`` with ``γ`` a small
#: multiple of ``n eps`` (the growth factor of partial pivoting, in practice a few); 4 covers
#: it, and ``tests/kcheck/test_friction_range_errors.py`` checks the bound against 50-digit
#: determinants of nearly singular systems.
DET_ROUNDING: float = 4.0

# --- Hertz contact -----------------------------------------------------------------------------

#: Principal curvatures, or curvature sums, that agree to this (relative) are equal
#: (nondimensional): a surface with both radii equal needs no direction, a contact with equal
#: sums is circular (no major axis), and ``sum_a <= sum_b`` holds to it. Radii converted from
#: the same typed number agree to rounding.
CURVATURE_RTOL: float = 1e-12
#: The AGM series of the elliptic integrals stops when a term is below this fraction of an ulp
#: of the sum (nondimensional): quadratic convergence makes the next term negligible.
AGM_ULP_FRACTION: float = 1e-3
#: A seated contact force at or below this fraction of the force scale is zero: the contact is
#: lifted (nondimensional, the solve's rounding is about 1e-15 of the scale).
LIFTED_RTOL: float = 1e-12


#: A coupling has a thermal centre only when the map from a body point to its thermal pose
#: shift, ``(alpha_body - alpha_base) dT I + [omega]x`` scaled to its largest entry, has a
#: determinant above this (nondimensional): below it the body and the base expand alike (to
#: about 1e-4 of the larger term in each direction) and the shift is a rigid motion.
THERMAL_CENTRE_DET: float = 1e-12

# --- reseat (time domain, MuJoCo) ----------------------------------------------------------------

#: The first-motion window ends when a contact point of the body has moved this share of the
#: retraction distance (nondimensional): far enough to see the sense of the motion above the
#: soft contacts' overlap changes (tenths of a µm against 10 µm at the default 100 µm).
RESEAT_WINDOW_SHARE: float = 0.1
#: A body that needs more than this many times the free-body time of its acceleration scale to
#: move the window's distance is held by friction (nondimensional): soft friction creeps (about
#: 2 µm/s in the Appendix A block at the defaults), a sliding body gets there within a few
#: free-body times (accelerations down to 1/400 of the scale still count as moving).
RESEAT_JAM_FACTOR: float = 20.0
#: The first motion is read no earlier than this many contact time constants after the release
#: (nondimensional; 4 ms at the first-motion run's 0.5 ms contacts): a contact the rigid motion
#: unloads at once comes out of its seated overlap only as the body moves, in 2 to 3 ms where
#: the seated forces are several times the load (random-3d-2473 s5: 2.3 ms), so a window closed
#: at 10 µm read it as kept. 8 was the best of 0, 5, 8, 12 and 16 on the agreement scenes
#: (404, 405, 410, 408, 407 of 417 agree); longer windows start to see the later motion.
RESEAT_RELEASE_TIME_CONSTANTS: float = 8.0
#: reseat: the longest back-off of a support (``retraction_time_ms``) as a share of a phase
#: (``duration_s``; nondimensional): the body needs the rest of phase 1 to move, so its first
#: motion is read and the support returns only once the back-off is over.
RESEAT_BACKOFF_SHARE: float = 0.5
#: reseat, a slow back-off (``retraction_time_ms`` > 0): a body whose contact points move this
#: share of the retraction distance while the support backs off has followed or left it
#: (nondimensional; a follower moves the whole retraction with the support). A held body moves
#: only by soft-friction creep, which the first-motion window would otherwise add up over the
#: whole back-off: up to 42 µm/s measured at the first-motion step (random-2d-6567 s1, seed 27;
#: about 70 µm/s as the step shrinks), 42 µm in a 1 s back-off against the 50 µm here
#: (docs/validation.md, "Held uniquely, a reading for slow back-offs").
RESEAT_BACKOFF_MOTION_SHARE: float = 0.5

#: A remaining support that is open and carries less than this share of the normal force over
#: the window's second half has lost contact (nondimensional); judged by force, because a kept
#: contact's soft overlap changes with its force by tenths of a µm.
RESEAT_LOST_SHARE: float = 0.01
#: A pressed rough contact sticks when its slip speed is below this share of retraction /
#: duration (nondimensional): creep is slower, sliding in the first motion much faster.
RESEAT_STICK_SHARE: float = 1e-3
#: error_estimate = this factor x |seat error(dt) - seat error(dt/2)| (nondimensional): first
#: order would make the reported (half-step) run's error about the difference; the seat error
#: at nm levels is part stick-slip noise, which halving the step changed by up to 1.3 x the
#: difference on the fixtures (mujoco 2.3.3, Appendix A), so twice it.
RESEAT_ESTIMATE_FACTOR: float = 2.0
#: The smallest seat error the simulation resolves (m), the floor of error_estimate: seat errors
#: of nm are the soft contacts' settling noise (their overlap is about 0.4 µm at the defaults,
#: and changes with each contact's force), not converging with the step; halving the step
#: changed fixtures' nm seat errors by up to 0.016 µm. 2 % of the default tolerance (1 µm).
RESEAT_SEAT_RESOLUTION: float = 2e-8
#: The settle goes on (in blocks of its own length, up to 1 s) until no contact point of the
#: body moves faster than this (m/s): the first motion is compared from a body at rest, and a
#: sliding body reaches 10 µm within a few ms (over 1e-2 m/s), 100 times faster.
RESEAT_REST_SPEED: float = 1e-4

# --- The first motion with contacts free to lift off (mechanics.lift_off) --------------------

#: Lemke's method takes no pivot on a tableau entry below this share of its column's largest
#: (nondimensional), nor tells ratios apart closer than this: twenty thousand roundings.
LEMKE_PIVOT_RTOL: float = 1e-12
#: An acceleration below this share of the free body's under the same wrench (nondimensional)
#: is rounding noise: the body is at rest; a contact whose normal acceleration is above it
#: lifts off. Lemke's pivots leave errors of a few thousand roundings, far below it.
LIFT_SHARE: float = 1e-9

# --- Contacts from the CAD (kcheck contacts) ---------------------------------------------------

#: Default gap tolerance of ``kcheck contacts`` as a fraction of the assembly's size
#: (nondimensional; of the diagonal of both parts' bounds): surfaces closer than this touch.
#: Tessellating a 6 mm ball with 0.3 mm edges leaves gaps of about 0.002 mm; 1e-3 of a 100 mm
#: assembly is 0.1 mm.
CONTACT_GAP_RTOL: float = 1e-3
#: Faces meeting at a dihedral angle below this (deg) belong to one smooth surface patch:
#: above the facet angles of any usable tessellation of a ball or pin (an 8-sided pin has
#: 45°, so coarser ones are not recognised), below the sharp edges of grooves and flats.
SMOOTH_PATCH_DEG: float = 30.0
#: A fitted plane, sphere or cylinder is accepted when the RMS distance of the patch's
#: vertices from it is below this fraction of the patch's size (nondimensional): STL's float32
#: coordinates and CAD tessellations put vertices on the surface to about 1e-7.
SURFACE_FIT_RTOL: float = 1e-4
#: A part is an extrusion along an axis when each face normal is within this angle (deg) of
#: perpendicular (its walls) or parallel (its end faces) to it; a planar coupling's extrusion
#: axis must be within it of z. STL's float32 tilts a facet by about 1e-5 deg; a draft angle
#: or a chamfer, by degrees.
EXTRUSION_DEG: float = 1.0
#: A certificate that friction cannot hold the body (a twist opening every kept contact
#: inside the dual of its friction cone, on which the wrench does work;
#: :mod:`kcheck.mechanics.holding_certificates`) decides the equilibrium question without its
#: own conic programme only when it clears every condition by this share of the twist's size
#: (nondimensional; the wrench scaled to 1): a hundred times clarabel's tolerances (1e-8), so
#: the programme gives the same answer; closer questions ask the programme.
HOLDING_CERTIFICATE_MARGIN: float = 1e-6
#: A certificate that friction holds (forces put back on the balance by a least-norm
#: correction) is accepted only for contact sets whose correction's reach ``|C| |(C^T C)^-1|``
#: (Frobenius norms of the kept contacts' unit wrenches, nondimensional) times the unit
#: roundoff stays below this: a hundredth of HOLDING_CERTIFICATE_MARGIN, so the rounding of
#: the inverse itself cannot move a slack by a visible share of the margin. Nearly dependent
#: contacts (reach above about 4.5e7) go to the conic programme.
HOLDING_CERTIFICATE_CONDITION: float = HOLDING_CERTIFICATE_MARGIN / 100
#: Newton steps (a count, nondimensional) of the certificate's search before a question is
#: left to its conic programme (on 1800 questions of 300 generated scenes every one was
#: decided within 33 steps, half within 5).
HOLDING_CERTIFICATE_STEPS: int = 40
#: Equilibrium questions asked together (a chunk of scenes; a count, nondimensional) below
#: which each goes straight to its conic programme: the certificates' batch costs a roughly
#: fixed 1.4 ms of numpy calls, more than a dozen programmes (0.14 ms each); break-even
#: about 15 questions.
HOLDING_CERTIFICATE_BATCH: int = 24
