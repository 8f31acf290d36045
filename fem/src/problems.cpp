#include <cmath>

#include "rgbmesh/fem/problem.hpp"
#include "rgbmesh/soup.hpp"

namespace rgbmesh::fem {

namespace {

// The surface gradient on the unit sphere of a function whose gradient in space is `ambient`
// at x: the part tangential to the sphere (normal x / |x|).
Vec3 on_unit_sphere(const Vec3& x, const Vec3& ambient) {
  const Vec3 normal = x * (1.0 / norm(x));
  return ambient - dot(ambient, normal) * normal;
}

}  // namespace

Problem sphere_harmonic() {
  Problem p;
  p.name = "sphere-harmonic";
  p.c = 0;
  p.source = [](const Vec3& x) { return 12.0 * x.x * x.y * x.z; };
  p.exact = ExactSolution{[](const Vec3& x) { return x.x * x.y * x.z; },
                          [](const Vec3& x) { return on_unit_sphere(x, Vec3(x.y * x.z, x.x * x.z, x.x * x.y)); }};
  p.dirichlet = p.exact->value;  // on a patch of the sphere, the boundary takes the exact values
  return p;
}

BiharmonicProblem sphere_biharmonic() {
  const Problem harmonic = sphere_harmonic();
  BiharmonicProblem p;
  p.name = "sphere-biharmonic";
  p.c = 1;
  p.source = [](const Vec3& x) { return 145.0 * x.x * x.y * x.z; };
  p.exact = harmonic.exact;
  p.exact_laplacian = [](const Vec3& x) { return -12.0 * x.x * x.y * x.z; };
  return p;
}

BiharmonicProblem sphere_biharmonic_peak(const Vec3& d_in, double kappa) {
  const Vec3 d = d_in * (1.0 / norm(d_in));
  const Problem peak = sphere_peak(d, kappa);
  BiharmonicProblem p;
  p.name = "sphere-biharmonic-peak";
  p.c = 1;
  // For u = h(t), t = x·d, on the unit sphere Δu = (1 - t²) h'' - 2 t h'. With g = exp(κ (t - 1)):
  // Δg = g (κ² (1 - t²) - 2 κ t) =: h1, h1' = g (κ³ (1 - t²) - 4 κ² t - 2 κ),
  // h1'' = g (κ⁴ (1 - t²) - 6 κ³ t - 6 κ²), and Δ²g = (1 - t²) h1'' - 2 t h1'.
  p.exact_laplacian = [d, kappa](const Vec3& x) {
    const double t = dot(x, d), g = std::exp(kappa * (t - 1.0));
    return g * (kappa * kappa * (1 - t * t) - 2 * kappa * t);
  };
  p.source = [d, kappa](const Vec3& x) {
    const double t = dot(x, d), g = std::exp(kappa * (t - 1.0)), s = 1 - t * t, k2 = kappa * kappa;
    const double h1p = g * (k2 * kappa * s - 4 * k2 * t - 2 * kappa);
    const double h1pp = g * (k2 * k2 * s - 6 * k2 * kappa * t - 6 * k2);
    return s * h1pp - 2 * t * h1p + g;
  };
  p.exact = peak.exact;
  return p;
}

Problem sphere_peak(const Vec3& d_in, double kappa, double c) {
  const Vec3 d = d_in * (1.0 / norm(d_in));
  Problem p;
  p.name = "sphere-peak";
  p.c = c;
  // u = g(t), t = x·d, g(t) = exp(κ (t - 1)): g' = κ g, g'' = κ² g.
  p.source = [d, kappa, c](const Vec3& x) {
    const double t = dot(x, d), g = std::exp(kappa * (t - 1.0));
    const double laplacian = kappa * kappa * g * (1.0 - t * t) - 2.0 * t * kappa * g;
    return -laplacian + c * g;
  };
  p.exact = ExactSolution{[d, kappa](const Vec3& x) { return std::exp(kappa * (dot(x, d) - 1.0)); },
                          [d, kappa](const Vec3& x) {
                            return on_unit_sphere(x, d * (kappa * std::exp(kappa * (dot(x, d) - 1.0))));
                          }};
  p.dirichlet = p.exact->value;
  return p;
}

Problem cube_cosine() {
  Problem p;
  p.name = "cube-cosine";
  p.c = 1;
  constexpr double pi = 3.14159265358979323846;
  p.source = [](const Vec3& x) {
    // On the faces x = 0 and x = 1 u is constant; a point of another face lies strictly inside
    // 0 < x < 1 (quadrature points are inside triangles, away from the cube's edges).
    const bool end_face = x.x <= 1e-12 || x.x >= 1.0 - 1e-12;
    return (end_face ? 1.0 : pi * pi + 1.0) * std::cos(pi * x.x);
  };
  // The ambient gradient (-π sin π x, 0, 0) is tangential to the faces along x and zero on the
  // faces x = 0, 1: it is the surface gradient everywhere.
  p.exact = ExactSolution{[](const Vec3& x) { return std::cos(pi * x.x); },
                          [](const Vec3& x) { return Vec3(-pi * std::sin(pi * x.x), 0.0, 0.0); }};
  return p;
}

Problem gaussian_source(const Vec3& x0, double sigma) {
  Problem p;
  p.name = "gaussian";
  p.c = 1.0;
  p.source = [x0, sigma](const Vec3& x) {
    const Vec3 r = x - x0;
    return std::exp(-dot(r, r) / (2.0 * sigma * sigma));
  };
  return p;
}

std::vector<std::string> builtin_problem_names() { return {"sphere-harmonic", "sphere-peak", "cube-cosine"}; }

Problem builtin_problem(const std::string& name) {
  if (name == "sphere-harmonic") return sphere_harmonic();
  if (name == "sphere-peak") return sphere_peak();
  if (name == "cube-cosine") return cube_cosine();
  std::string names;
  for (const auto& n : builtin_problem_names()) names += (names.empty() ? "" : ", ") + n;
  throw InputError("unknown problem '" + name + "' (built in: " + names + ")");
}

}  // namespace rgbmesh::fem
