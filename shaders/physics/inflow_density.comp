#version 450
#extension GL_GOOGLE_include_directive : require
// Inflow of density and temperature: what the sources add this step, for advection to add after it
// moves the fields (ρ_next = A(ρ) + inflowDensity). At fluid cells c with centre p = c + ½, over the
// sources s of the table (inflow_sources.glsl), with coverage w_s(p) and noise factor
// n_s(p) = 1 + amplitude_s·(2·noise_s(p) − 1):
//   set sources:  target = max_s (density_s · n_s(p) · w_s(p)),   added = Σ_add dt·density_s·n_s(p)·w_s(p),
//   inflowDensity(c) = max(target − ρ(c), 0) + added;  temperature alike with temperature_s (no noise).
// 0 at other cells. The dispatch covers only the box of cells low + gid that holds every source
// (computed by the host); the host zeroes the outputs first. Index names in obstacle_flags.glsl.
#include "obstacle_flags.glsl"
#include "inflow_sources.glsl"
layout(local_size_x_id = 0, local_size_y_id = 1, local_size_z_id = 2) in;

layout(binding = 0) uniform samplerBuffer flags;
layout(binding = 1) uniform samplerBuffer density;
layout(binding = 2) uniform samplerBuffer temperature;
layout(binding = 3) uniform samplerBuffer table;
layout(std430, binding = 4) writeonly buffer DensityInflow { float densityInflow[]; };
layout(std430, binding = 5) writeonly buffer TemperatureInflow { float temperatureInflow[]; };
layout(push_constant) uniform Push {
  ivec3 size;
  int sources;
  ivec3 low;
  float dt;
};

void main() {
  const ivec3 c = low + dispatch_cell();
  if (!in_grid(c, size)) return;
  const int item = cell_index(c, size);
  float inflowRho = 0.0;
  float inflowTemperature = 0.0;
  if (is_fluid(cell_flag(flags, c, size))) {
    const vec3 p = vec3(c) + 0.5;
    float targetRho = 0.0, targetTemperature = 0.0, addedRho = 0.0, addedTemperature = 0.0;
    for (int i = 0; i < sources; ++i) {
      const Source s = read_source(table, i);
      const float w = source_coverage(s, p);
      if (w <= 0.0) continue;
      const float modulation = s.noiseAmplitude > 0.0 ? 1.0 + s.noiseAmplitude * (2.0 * source_noise(s, p) - 1.0) : 1.0;
      const float rho = s.density * modulation * w;
      const float temp = s.temperature * w;
      if (s.mode == 0) {
        targetRho = max(targetRho, rho);
        targetTemperature = max(targetTemperature, temp);
      } else {
        addedRho += dt * rho;
        addedTemperature += dt * temp;
      }
    }
    inflowRho = max(targetRho - texelFetch(density, item).x, 0.0) + addedRho;
    inflowTemperature = max(targetTemperature - texelFetch(temperature, item).x, 0.0) + addedTemperature;
  }
  densityInflow[item] = inflowRho;
  temperatureInflow[item] = inflowTemperature;
}
