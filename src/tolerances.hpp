#pragma once
// Every tolerance of the analysis in one place, each with the reason for its value. Messages
// that quote one are built from the constant (shortest_text), so that a message and the check
// it reports cannot drift apart. The options a caller may change (SolveOptions) are not here.
#include <limits>

namespace stiffmsa::detail {

// ---- model checks (validate) -------------------------------------------------------------

// |a × b| of unit vectors below this: parallel axes.
inline constexpr double kParallelTolerance = 1e-9;
// Smallest over largest singular value of a custom joint's free rows below this: dependent.
inline constexpr double kRankTolerance = 1e-9;
// Symmetry and semi-definiteness of a user's matrix, relative to max|M|.
inline constexpr double kMatrixTolerance = 1e-9;
// Smallest over largest eigenvalue below this: not definite.
inline constexpr double kDefiniteTolerance = 1e-12;
// A free-free stiffness must not resist rigid motions: ‖K·R‖₂ relative to ‖K‖₂·‖R‖₂.
inline constexpr double kFreeFreeTolerance = 1e-6;
// A link shorter than this, relative to max(1, model extent), has no length.
inline constexpr double kLengthTolerance = 1e-12;

// ---- elements ----------------------------------------------------------------------------

// A beam's axis this close to parallel (|x × z|) to global Z takes global X as its reference.
inline constexpr double kReferenceParallel = 1e-9;
// A clamped CAD stiffness whose smallest over largest eigenvalue is below this is singular.
inline constexpr double kClampedSpread = 1e-12;

// ---- solvers -----------------------------------------------------------------------------

// The least reciprocal condition estimate of the scaled K a frame solve accepts. A member's
// wrenches come from differences of its ends' deflections, K12·Δt, which lose about as many
// digits as K's condition has: measured on slender members near this bar, deflections and
// wrenches stay within ~3·10⁻¹¹ of the mixed LU's (docs/theory.md §7.3), ~10 digits.
inline constexpr double kFrameLeastRcond = 1e-6;
// Iterative refinement runs where some column's backward error over the reciprocal condition
// exceeds this: a heuristic sign that digits were lost (docs/theory.md §7).
inline constexpr double kRefineAbove = 1e-14;
// Pivots of the rank-revealing QR and LU of a singular system below this fraction of the
// largest are zero: the null spaces of free motions and redundancies.
inline constexpr double kRankRevealingPivot = 1e-10;

// ---- analysis ----------------------------------------------------------------------------

// The least model size (m): the lever that weighs moments against forces is never below 1 mm.
inline constexpr double kLeastModelSize = 1e-3;
// Loads and reactions out of balance beyond this, relative, fail an accuracy check.
inline constexpr double kEquilibriumTolerance = 1e-8;
// A bordered solve (free motions removed) whose relative residual exceeds this has loads
// acting along a free motion.
inline constexpr double kLoadAlongFreeMotion = 1e-8;
// A quantity of a singular system below this fraction of the largest of its kind (an internal
// wrench's variation over the redundancies, an end's share of a free motion) is rounding:
// determined, or not moving.
inline constexpr double kNegligibleShare = 1e-8;
// Entries of a unit equilibrated null vector below this are rounding.
inline constexpr double kNegligibleNullEntry = 1e-8;
// Border entries (null vectors appended to a singular system) below this fraction of their
// column's largest are dropped: rounding, which would only add fill.
inline constexpr double kBorderDrop = 1e-14;
// A determined component of an undetermined wrench below this fraction of the determined ones
// (moments divided by the length) is rounding, and shown as 0.
inline constexpr double kRoundOff = 1e-12;
// A connection, link or end effector takes part in a free motion where its motion there
// exceeds this fraction of the largest motion of a link end in it (rotations weighed by the
// model's size): below it, the null vector's rounding.
inline constexpr double kTakesPart = 1e-6;
// Two points closer than this fraction of the model's size stand at the same place.
inline constexpr double kSamePlace = 1e-9;
// Beyond this spread of a compliance's eigenvalues the smallest is at rounding level of the
// largest: directions held rigidly.
inline constexpr double kRigidSpread = 1e14;
// Below this fraction of the largest compliance of a block, a compliance is rounding: the
// direction is held rigidly.
inline constexpr double kRigidCompliance = 1e-12;

// ---- critical load (docs/theory.md §14) ----------------------------------------------------

// An eigenvalue μ = 1/λ of the load terms' eigenproblem whose imaginary part is within this
// fraction of its real part is real: a double root that rounding split into a complex pair.
inline constexpr double kRealEigenvalue = 1e-8;
// μ below this fraction of the largest |μ| is rounding of a zero (the constraint rows' infinite
// λ), not a critical load factor beyond 10¹⁰ times the smallest.
inline constexpr double kLeastLoadEigenvalue = 1e-10;
// Up to 6 times this many load directions (the reduced eigenproblem's size, theory.md §14.3) the
// eigenproblem is solved densely, every eigenvalue at once; beyond, by Arnoldi's iteration,
// whose cost grows with the model, not with its cube (bench/README.md: a column of 100 beams,
// 1.2 s densely, 0.03 s so).
inline constexpr int kMostDenseNodes = 30;
// Arnoldi's iteration stops where the Ritz pair's residual is below this fraction of the
// largest Ritz value (and a new direction below it is no new direction).
inline constexpr double kArnoldiTolerance = 1e-13;
// Arnoldi's iteration takes at most this many steps (one solve each).
inline constexpr int kMostArnoldiSteps = 400;
// A direction of the wrenches a node's load terms give (its rows of K_L) below this fraction of
// the largest is rounding of a zero: a beam's zero rows turned to global axes leave some 1e-16
// of the others. The same fraction of the first pivot ends the elimination that finds the rank
// of the reduced eigenproblem (theory.md §14.3).
inline constexpr double kLoadTermRank = 1e-13;
// Inverse iteration for the critical mode moves its shift off the eigenvalue by this fraction
// of the reduced matrix's largest entry, so that the LU's pivots stay finite.
inline constexpr double kInverseIterationShift = 1e-14;
// The reduced eigenproblem's eigenvalues by the double-shift QR iteration (critical_load.hpp,
// eigenvalues_of): a subdiagonal entry below this fraction of its two diagonal neighbours is
// zero (the matrix splits there), and the iteration gives up after this many sweeps per
// eigenvalue on average (Eigen's EigenSolver then decides), with an exceptional shift every
// kQrExceptionalShiftEvery sweeps without a split.
inline constexpr double kQrSplit = std::numeric_limits<double>::epsilon();
inline constexpr int kMostQrSweepsPerEigenvalue = 40;
inline constexpr int kQrExceptionalShiftEvery = 10;
// The exceptional shifts, each less the trailing diagonal entry: their sum in units of the
// trailing subdiagonal's size (their product is that size squared), a complex pair unlike any
// the iteration was cycling on (LAPACK's dlahqr: 0.75·size ± 0.66i·size).
inline constexpr double kQrExceptionalShiftSum = 1.5;
// The parts of a buckling mode that a description names: those moving at least this fraction
// of the most moving one.
inline constexpr double kModeShare = 0.25;
// Parts of a buckling mode whose sizes agree to this fraction of the largest move alike (a
// symmetric structure's mirror parts, whose sizes rounding splits): named in the model's order.
inline constexpr double kModeTie = 1e-9;

}  // namespace stiffmsa::detail
