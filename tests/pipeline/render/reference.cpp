#include "tests/pipeline/render/reference.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace smokesvd::testing::reference {
namespace {

double real(int64_t v) { return static_cast<double>(v); }

double at(const std::vector<double>& v, const GridSize& g, int64_t x, int64_t y, int64_t z) {
  if (x < 0 || y < 0 || z < 0 || x >= g.x || y >= g.y || z >= g.z) return 0.0;
  return v[static_cast<std::size_t>((z * g.y + y) * g.x + x)];
}

bool insidePadded(const Vec3& p, const GridSize& g) {
  const double size[3] = {static_cast<double>(g.x), static_cast<double>(g.y), static_cast<double>(g.z)};
  for (int a = 0; a < 3; ++a)
    if (p[a] <= -0.5 || p[a] >= size[a] + 0.5) return false;
  return true;
}

// [t0, t1] of the ray inside the box [-1/2, N + 1/2], t0 >= 0.
std::pair<double, double> rayBox(const Ray& ray, const GridSize& g) {
  const double size[3] = {static_cast<double>(g.x), static_cast<double>(g.y), static_cast<double>(g.z)};
  double t0 = 0, t1 = 1e300;
  for (int a = 0; a < 3; ++a) {
    const double lo = -0.5, hi = size[a] + 0.5;
    if (std::abs(ray.direction[a]) < 1e-12) {
      if (ray.origin[a] <= lo || ray.origin[a] >= hi) return {1, 0};
      continue;
    }
    const double ta = (lo - ray.origin[a]) / ray.direction[a], tb = (hi - ray.origin[a]) / ray.direction[a];
    t0 = std::max(t0, std::min(ta, tb));
    t1 = std::min(t1, std::max(ta, tb));
  }
  return {t0, t1};
}

}  // namespace

double sampleZero(const std::vector<double>& volume, const GridSize& g, const Vec3& p) {
  const double qx = p[0] - 0.5, qy = p[1] - 0.5, qz = p[2] - 0.5;
  const double fx = std::floor(qx), fy = std::floor(qy), fz = std::floor(qz);
  const auto x = static_cast<int64_t>(fx), y = static_cast<int64_t>(fy), z = static_cast<int64_t>(fz);
  const double ax = qx - fx, ay = qy - fy, az = qz - fz;
  double value = 0;
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
    const double w = (dx ? ax : 1 - ax) * (dy ? ay : 1 - ay) * (dz ? az : 1 - az);
    value += w * at(volume, g, x + dx, y + dy, z + dz);
  }
  return value;
}

double sampleClamped(const std::vector<double>& volume, const GridSize& g, const Vec3& p) {
  const Vec3 clamped = {std::clamp(p[0], 0.5, real(g.x) - 0.5), std::clamp(p[1], 0.5, real(g.y) - 0.5),
                        std::clamp(p[2], 0.5, real(g.z) - 0.5)};
  const double qx = clamped[0] - 0.5, qy = clamped[1] - 0.5, qz = clamped[2] - 0.5;
  const auto x = static_cast<int64_t>(std::floor(qx)), y = static_cast<int64_t>(std::floor(qy)),
             z = static_cast<int64_t>(std::floor(qz));
  const double ax = qx - static_cast<double>(x), ay = qy - static_cast<double>(y), az = qz - static_cast<double>(z);
  double value = 0;
  for (int c = 0; c < 8; ++c) {
    const int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
    const double w = (dx ? ax : 1 - ax) * (dy ? ay : 1 - ay) * (dz ? az : 1 - az);
    value += w * at(volume, g, std::min(x + dx, g.x - 1), std::min(y + dy, g.y - 1),
                    std::min(z + dz, g.z - 1));
  }
  return value;
}

std::vector<double> lightTransmittance(const std::vector<double>& density, const GridSize& g,
                                       const render::DirectionalLight& light) {
  const Vec3 l = glm::normalize(light.direction);
  std::vector<double> result;
  for (int z = 0; z < g.z; ++z)
    for (int y = 0; y < g.y; ++y)
      for (int x = 0; x < g.x; ++x) {
        const Vec3 centre = {x + 0.5, y + 0.5, z + 0.5};
        double optical = 0;
        for (int j = 0;; ++j) {
          const Vec3 p = centre + ((j + 0.5) * light.step) * l;
          if (!insidePadded(p, g)) break;
          optical += sampleZero(density, g, p);
        }
        result.push_back(std::exp(-light.absorption * light.step * optical));
      }
  return result;
}

std::vector<double> render(const std::vector<double>& density, const GridSize& g, const std::vector<Camera>& cameras,
                           const render::RenderSettings& s) {
  std::vector<double> shadow;
  if (s.light) shadow = lightTransmittance(density, g, *s.light);
  std::vector<double> images;
  for (const Camera& camera : cameras)
    for (int r = 0; r < camera.height; ++r)
      for (int c = 0; c < camera.width; ++c) {
        const Ray ray = camera.ray(c + 0.5, r + 0.5);
        const auto [t0, t1] = rayBox(ray, g);
        double radiance = 0, transmittance = 1;
        for (int k = 0;; ++k) {
          const double t = t0 + (k + 0.5) * s.step;
          if (t >= t1) break;
          const Vec3 p = ray.origin + t * ray.direction;
          const double sigma = sampleZero(density, g, p);
          const double source = s.ambient + (s.light ? s.light->intensity * sampleClamped(shadow, g, p) : 0.0);
          const double alpha = 1 - std::exp(-s.absorption * sigma * s.step);
          radiance += transmittance * alpha * source;
          transmittance *= 1 - alpha;
        }
        images.push_back(radiance);
      }
  return images;
}

std::vector<double> lift(const std::vector<double>& images, const std::vector<Camera>& cameras, const GridSize& g) {
  std::vector<double> lifted;
  std::size_t offset = 0;
  for (const Camera& camera : cameras) {
    auto pixel = [&](int64_t c, int64_t r) {
      if (c < 0 || r < 0 || c >= camera.width || r >= camera.height) return 0.0;
      return images[offset + static_cast<std::size_t>(r * camera.width + c)];
    };
    for (int z = 0; z < g.z; ++z)
      for (int y = 0; y < g.y; ++y)
        for (int x = 0; x < g.x; ++x) {
          const auto uv = camera.project({x + 0.5, y + 0.5, z + 0.5});
          double value = 0;
          if (uv) {
            const double qu = (*uv)[0] - 0.5, qv = (*uv)[1] - 0.5;
            const auto c = static_cast<int64_t>(std::floor(qu)), r = static_cast<int64_t>(std::floor(qv));
            const double fu = qu - static_cast<double>(c), fv = qv - static_cast<double>(r);
            value = (1 - fv) * ((1 - fu) * pixel(c, r) + fu * pixel(c + 1, r)) +
                    fv * ((1 - fu) * pixel(c, r + 1) + fu * pixel(c + 1, r + 1));
          }
          lifted.push_back(value);
        }
    offset += static_cast<std::size_t>(camera.width * camera.height);
  }
  return lifted;
}

std::vector<double> rotate(const std::vector<double>& volume, int64_t channels, const GridSize& g,
                           double angleDegrees) {
  const double a = angleDegrees * std::numbers::pi / 180.0, ca = std::cos(a), sa = std::sin(a);
  const Vec3 centre = g.centre();
  const auto voxels = static_cast<std::size_t>(g.z * g.y * g.x);
  std::vector<double> rotated;
  for (int64_t ch = 0; ch < channels; ++ch) {
    const std::vector<double> slice(volume.begin() + static_cast<std::ptrdiff_t>(ch * static_cast<int64_t>(voxels)),
                                    volume.begin() + static_cast<std::ptrdiff_t>((ch + 1) * static_cast<int64_t>(voxels)));
    for (int z = 0; z < g.z; ++z)
      for (int y = 0; y < g.y; ++y)
        for (int x = 0; x < g.x; ++x) {
          const Vec3 d = Vec3{x + 0.5, y + 0.5, z + 0.5} - centre;
          const Vec3 source = centre + Vec3{d[0] * ca - d[2] * sa, d[1], d[0] * sa + d[2] * ca};
          rotated.push_back(sampleZero(slice, g, source));
        }
  }
  return rotated;
}

}  // namespace smokesvd::testing::reference
