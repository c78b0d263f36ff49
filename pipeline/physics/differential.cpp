#include "pipeline/physics/differential.h"

#include <array>
#include <string>

#include "pipeline/physics/grid.h"

namespace smokesvd::physics {
namespace {

constexpr std::array<uint32_t, 3> kWorkgroup{16, 4, 1};

struct GridPush {
  int32_t nx, ny, nz;
};

// Records one dispatch of a gradient-stencil kernel over the cells of `grid`.
void run(Stream& stream, const char* shader, std::vector<int32_t> constants, const GridSize& grid,
         std::initializer_list<Arg> args) {
  const GridPush push{static_cast<int32_t>(grid.x), static_cast<int32_t>(grid.y), static_cast<int32_t>(grid.z)};
  const std::array<uint32_t, 3> groups{static_cast<uint32_t>((grid.x + kWorkgroup[0] - 1) / kWorkgroup[0]),
                                       static_cast<uint32_t>((grid.y + kWorkgroup[1] - 1) / kWorkgroup[1]),
                                       static_cast<uint32_t>(grid.z)};
  stream.dispatch(stream.kernel(shader, kWorkgroup, std::move(constants)), args, push, groups);
}

int32_t staggered(Staggering staggering) { return staggering == Staggering::Mac ? 1 : 0; }

}  // namespace

void macToCentred(Stream& stream, const Tensor& mac, const Tensor& centred) {
  const GridSize grid = vectorGrid(mac, "mac to centred: MAC velocity");
  requireVector(centred, grid, "mac to centred: centred velocity");
  run(stream, "physics/mac_centred", {1}, grid, {mac, centred});
}

void centredToMac(Stream& stream, const Tensor& centred, const Tensor& mac) {
  const GridSize grid = vectorGrid(centred, "centred to mac: centred velocity");
  requireVector(mac, grid, "centred to mac: MAC velocity");
  run(stream, "physics/mac_centred", {0}, grid, {centred, mac});
}

void divergence(Stream& stream, const Tensor& velocity, Staggering staggering, const Tensor& out) {
  const GridSize grid = vectorGrid(velocity, "divergence: velocity");
  requireVolume(out, grid, "divergence: output");
  run(stream, "physics/divergence", {staggered(staggering)}, grid, {velocity, out});
}

void divergenceBackward(Stream& stream, Staggering staggering, const Tensor& gradOut, const Tensor& gradVelocity) {
  const GridSize grid = vectorGrid(gradVelocity, "divergence backward: velocity gradient");
  requireVolume(gradOut, grid, "divergence backward: upstream gradient");
  run(stream, "physics/divergence_adjoint", {staggered(staggering)}, grid, {gradOut, gradVelocity});
}

void curl(Stream& stream, const Tensor& velocity, const Tensor& out) {
  const GridSize grid = vectorGrid(velocity, "curl: velocity");
  requireVector(out, grid, "curl: output");
  run(stream, "physics/curl", {}, grid, {velocity, out});
}

void curlBackward(Stream& stream, const Tensor& gradOut, const Tensor& gradVelocity) {
  const GridSize grid = vectorGrid(gradVelocity, "curl backward: velocity gradient");
  requireVector(gradOut, grid, "curl backward: upstream gradient");
  run(stream, "physics/curl_adjoint", {}, grid, {gradOut, gradVelocity});
}

void gradientNormSquared(Stream& stream, const Tensor& velocity, const Tensor& out) {
  const GridSize grid = vectorGrid(velocity, "gradient norm: velocity");
  requireVolume(out, grid, "gradient norm: output");
  run(stream, "physics/gradient_norm", {}, grid, {velocity, out});
}

void gradientNormSquaredBackward(Stream& stream, const Tensor& velocity, const Tensor& gradOut,
                                 const Tensor& gradVelocity) {
  const GridSize grid = vectorGrid(velocity, "gradient norm backward: velocity");
  requireVolume(gradOut, grid, "gradient norm backward: upstream gradient");
  requireVector(gradVelocity, grid, "gradient norm backward: velocity gradient");
  run(stream, "physics/gradient_norm_adjoint", {}, grid, {velocity, gradOut, gradVelocity});
}

}  // namespace smokesvd::physics
