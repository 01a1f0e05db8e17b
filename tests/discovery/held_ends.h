#pragma once
/// @file
/// The platen-read stiffness of an elastic cylinder whose end faces rigid platens hold (no slip),
/// for the generator: a Ritz solution of axisymmetric elasticity, independent of the model's
/// fitted end-zone law (diagnose's held_end_shortening) and of the simulator. The fields are
/// polynomials: u_r = r rho^(2i) (1 - s^2) s^(2j) (zero on the held faces), u_z = -e z +
/// rho^(2i) (1 - s^2) s^(2j+1) (the faces' approach prescribed), rho = r / R, s = 2 z / L - 1,
/// i, j < 6; the energy is integrated by 40 x 40 Gauss points. Against the deal.II reference
/// (`cosim reference --interface bonded`, elastic, mesh 16, nu 0.25), E_app / E at L/D 1/2, 1
/// and 2: 1.07727 / 1.03647 / 1.01785 against 1.07719 / 1.03646 / 1.01777 (a Ritz solution
/// bounds the stiffness from above; 1e-4 of it is the corner's slow convergence).

#include <cmath>
#include <utility>
#include <vector>

namespace discovery
{
  /// Gauss-Legendre points and weights on [-1, 1] (Newton on the Legendre polynomial).
  inline void gauss_legendre(const int n, std::vector<double> &x, std::vector<double> &w)
  {
    const double pi = 3.14159265358979323846;
    x.assign(n, 0);
    w.assign(n, 0);
    for (int k = 0; k < n; ++k)
    {
      double t = std::cos(pi * (k + 0.75) / (n + 0.5)), dp = 1;
      for (int it = 0; it < 100; ++it)
      {
        double p0 = 1, p1 = t; // P_0, P_1; up to P_n
        for (int m = 2; m <= n; ++m)
        {
          const double p2 = ((2 * m - 1) * t * p1 - (m - 1) * p0) / m;
          p0              = p1;
          p1              = p2;
        }
        dp               = n * (t * p1 - p0) / (t * t - 1);
        const double dt  = p1 / dp;
        t -= dt;
        if (std::abs(dt) < 1e-15)
          break;
      }
      x[k] = t;
      w[k] = 2 / ((1 - t * t) * dp * dp);
    }
  }

  /// E_app / E of an elastic cylinder of slenderness L/D and Poisson's ratio nu whose end faces
  /// rigid platens hold: the axial force over (area E strain).
  inline double held_stiffening(const double slenderness, const double nu)
  {
    const int n = 6, nq = 40;
    const double L = 2 * slenderness; // radius 1
    const double lam = nu / ((1 + nu) * (1 - 2 * nu)), mu = 1 / (2 * (1 + nu)); // E = 1
    std::vector<double> xq, wq;
    gauss_legendre(nq, xq, wq);
    // strains (rr, tt, zz, rz engineering) of each basis field at each point, then the imposed one
    const int nb  = 2 * n * n;
    const int npt = nq * nq;
    std::vector<double> strain(static_cast<std::size_t>(nb + 1) * npt * 4, 0.0), weight(npt);
    const auto at = [&](int b, int p, int c) -> double & {
      return strain[(static_cast<std::size_t>(b) * npt + p) * 4 + c];
    };
    const auto power = [](double v, int k) { return k <= 0 ? 1.0 : std::pow(v, k); };
    for (int a = 0; a < nq; ++a)
      for (int c = 0; c < nq; ++c)
      {
        const int p    = a * nq + c;
        const double r = 0.5 * (xq[a] + 1), s = xq[c];
        weight[p]      = 0.5 * wq[a] * r * wq[c]; // r dr ds (dz = L/2 ds cancels in E_app)
        int b          = 0;
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j, ++b)
          {
            const int k     = 2 * j;
            const double q  = (1 - s * s) * power(s, k);
            const double dq = -2 * power(s, k + 1) + (k > 0 ? (1 - s * s) * k * power(s, k - 1) : 0);
            at(b, p, 0) = (2 * i + 1) * power(r, 2 * i) * q;
            at(b, p, 1) = power(r, 2 * i) * q;
            at(b, p, 3) = power(r, 2 * i + 1) * dq * 2 / L;
          }
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j, ++b)
          {
            const int k     = 2 * j + 1;
            const double q  = (1 - s * s) * power(s, k);
            const double dq = -2 * power(s, k + 1) + (1 - s * s) * k * power(s, k - 1);
            at(b, p, 2) = power(r, 2 * i) * dq * 2 / L;
            at(b, p, 3) = i > 0 ? 2 * i * power(r, 2 * i - 1) * q : 0;
          }
        at(nb, p, 2) = -1; // the imposed unit shortening
      }
    const auto energy = [&](int x, int y) { // the bilinear form of the strain energy
      double e = 0;
      for (int p = 0; p < npt; ++p)
      {
        const double *u = &at(x, p, 0), *v = &at(y, p, 0);
        const double tu = u[0] + u[1] + u[2], tv = v[0] + v[1] + v[2];
        e += weight[p] * (lam * tu * tv + 2 * mu * (u[0] * v[0] + u[1] * v[1] + u[2] * v[2]) +
                          mu * u[3] * v[3]);
      }
      return e;
    };
    // K c = -f by Gaussian elimination with partial pivoting (K symmetric positive definite)
    std::vector<std::vector<double>> K(nb, std::vector<double>(nb + 1));
    for (int x = 0; x < nb; ++x)
    {
      for (int y = x; y < nb; ++y)
        K[x][y] = K[y][x] = energy(x, y);
      K[x][nb] = -energy(x, nb);
    }
    std::vector<double> f(nb);
    for (int x = 0; x < nb; ++x)
      f[x] = -K[x][nb];
    for (int c = 0; c < nb; ++c)
    {
      int pivot = c;
      for (int x = c + 1; x < nb; ++x)
        if (std::abs(K[x][c]) > std::abs(K[pivot][c]))
          pivot = x;
      std::swap(K[c], K[pivot]);
      for (int x = c + 1; x < nb; ++x)
      {
        const double m = K[x][c] / K[c][c];
        for (int y = c; y <= nb; ++y)
          K[x][y] -= m * K[c][y];
      }
    }
    std::vector<double> coef(nb);
    for (int x = nb - 1; x >= 0; --x)
    {
      double v = K[x][nb];
      for (int y = x + 1; y < nb; ++y)
        v -= K[x][y] * coef[y];
      coef[x] = v / K[x][x];
    }
    // twice the minimum energy, a(e0, e0) + coef . f (K coef = -f): E_app = that / volume
    double twice_energy = energy(nb, nb);
    for (int x = 0; x < nb; ++x)
      twice_energy += coef[x] * f[x];
    double volume = 0;
    for (int p = 0; p < npt; ++p)
      volume += weight[p];
    return twice_energy / volume;
  }

  /// c of the held cylinder's platen displacement (q / E) (L - c D) [-].
  inline double held_shortening(const double slenderness, const double nu)
  {
    return (1 - 1 / held_stiffening(slenderness, nu)) * slenderness;
  }
} // namespace discovery
