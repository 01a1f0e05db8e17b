// fem::Parameters::free_body: an elastic body with no prescribed motion (impact and wave checks).
#include <fem/steel_body.h>

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace
{
  fem::SteelBody free_box(bool free_body, fem::SteelModel model = fem::SteelModel::elastic)
  {
    fem::BodyGeometry g;
    g.shape     = fem::BodyShape::box;
    g.size_x    = 16e-3;
    g.size_y    = 16e-3;
    g.thickness = 8e-3;
    g.side      = fem::BodySide::below;
    fem::Parameters p;
    p.model        = model;
    p.element_size = 2e-3;
    p.free_body    = free_body;
    return fem::SteelBody(g, p);
  }
} // namespace

TEST(FreeBody, MomentumIsTheImpulseOfTheContactForces)
{
  // a constant push on the contact face for longer than a wave transit (the wave reflects from
  // the far face): a free body keeps every bit of the impulse, a held one gives it to the frame
  const double dt = 1e-7, F = -1.0;
  for (const bool free_body : {true, false})
  {
    fem::SteelBody body = free_box(free_body);
    ASSERT_LT(dt, body.stable_time_step());
    std::vector<double> f(3 * body.n_contact_nodes(), 0.0);
    for (std::size_t i = 0; i < body.n_contact_nodes(); ++i)
      f[3 * i + 2] = F;
    const int n_steps = 60; // 6 us, about four transits of the 8 mm block
    for (int n = 0; n < n_steps; ++n)
    {
      body.add_contact_forces(f);
      body.step(n * dt, dt);
    }
    const auto m = body.nodal_masses();
    const auto v = body.mesh_snapshot().velocity;
    double p     = 0;
    for (std::size_t i = 2; i < v.size(); i += 3)
      p += m[i / 3] * v[i];
    // central differences start with half a step (v at -dt/2 = 0 to v at dt/2), so the impulse
    // is F (n - 1/2) dt, exactly up to round-off
    const double impulse = F * body.n_contact_nodes() * (n_steps - 0.5) * dt;
    if (free_body)
    {
      EXPECT_NEAR(p / impulse, 1.0, 1e-10);
      EXPECT_NEAR(body.reaction_force(), 0.0, 0.0);
    }
    else
      EXPECT_LT(std::abs(p / impulse), 0.9) << "a held body must pass impulse to the frame";
  }
}

TEST(FreeBody, HasNoPrescribedMotion)
{
  fem::SteelBody body = free_box(true);
  EXPECT_THROW(body.set_loaded_face_velocity([](double) { return 1.0; }), std::logic_error);
  EXPECT_THROW(free_box(true, fem::SteelModel::rigid), std::invalid_argument);
}
