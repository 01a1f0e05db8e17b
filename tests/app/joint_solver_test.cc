// Broyden's method of the joint calibration (cosim calibrate --simulate --with-bts) on closed
// forms whose roots are known.
#include <app/joint_solver.h>

#include <gtest/gtest.h>

#include <cmath>

using app::Matrix2;
using app::Vector2;

// A power law in two unknowns is linear in their logarithms: Broyden's method from a wrong
// Jacobian guess must still find the root where UCS is x 1.6 and BTS x 1.5.
TEST(JointSolver, FindsTheRootOfAPowerLawFromAWrongGuess)
{
  const double t0 = std::log(1.6), t1 = std::log(1.5);
  const auto r    = [&](const Vector2 &x) -> Vector2 {
    // the true slopes (0.62, 0.08; 0.95, 0.45) differ from the guess below; a mild curvature
    return {0.62 * x[0] + 0.08 * x[1] + 0.05 * x[0] * x[0] - t0, 0.95 * x[0] + 0.45 * x[1] - t1};
  };
  const Matrix2 guess{{{0.7, 0.1}, {0.8, 0.4}}};
  int calls = 0;
  const auto j = app::solve_broyden(r, {0, 0}, guess, 1e-4, 20, std::log(2.0),
                                    [&calls](const Vector2 &, const Vector2 &) { ++calls; });
  ASSERT_TRUE(j.converged);
  EXPECT_EQ(calls, j.evaluations);
  const Vector2 f = r(j.x);
  EXPECT_LE(std::abs(f[0]), 1e-4);
  EXPECT_LE(std::abs(f[1]), 1e-4);
  // each evaluation is minutes of coupled runs: a guess this far off must not cost more than 10
  EXPECT_LE(j.evaluations, 10);
}

// A step is limited to max_step in each component, so a far root takes several steps and a bad
// Jacobian guess cannot throw the runs to an absurd strength.
TEST(JointSolver, LimitsEachStep)
{
  const auto r = [](const Vector2 &x) -> Vector2 { return {x[0] - 3.0, x[1] + 2.0}; };
  Vector2 last{0, 0};
  double largest = 0;
  const auto j = app::solve_broyden(r, {0, 0}, {{{1, 0}, {0, 1}}}, 1e-9, 20, 0.5,
                                    [&](const Vector2 &x, const Vector2 &) {
                                      largest = std::max({largest, std::abs(x[0] - last[0]), std::abs(x[1] - last[1])});
                                      last    = x;
                                    });
  ASSERT_TRUE(j.converged);
  EXPECT_NEAR(j.x[0], 3.0, 1e-9);
  EXPECT_NEAR(j.x[1], -2.0, 1e-9);
  EXPECT_LE(largest, 0.5 + 1e-12);
  EXPECT_EQ(j.evaluations, 7); // the start and six steps of 0.5 to reach 3
}

// A singular Jacobian (the BTS does not depend on either unknown) stops the solver, unconverged,
// instead of dividing by zero.
TEST(JointSolver, StopsOnASingularJacobian)
{
  const auto r = [](const Vector2 &x) -> Vector2 { return {x[0] + x[1] - 1.0, 0.5}; };
  const auto j = app::solve_broyden(r, {0, 0}, {{{1, 1}, {0, 0}}}, 1e-6, 20, 1.0);
  EXPECT_FALSE(j.converged);
  EXPECT_EQ(j.evaluations, 1);
}
