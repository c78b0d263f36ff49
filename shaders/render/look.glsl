// The look of a render, read from a small buffer (pipeline/render/look.h) instead of push constants so
// that a recorded stream renders with new settings after an upload:
//   look = [absorption, ambient, light intensity, light absorption, light direction x, y, z (unit), 0]
#ifndef SMOKESVD_LOOK_GLSL
#define SMOKESVD_LOOK_GLSL

float look_absorption(samplerBuffer look) { return texelFetch(look, 0).x; }
float look_ambient(samplerBuffer look) { return texelFetch(look, 1).x; }
float look_intensity(samplerBuffer look) { return texelFetch(look, 2).x; }
float look_light_absorption(samplerBuffer look) { return texelFetch(look, 3).x; }
vec3 look_light_direction(samplerBuffer look) {
  return vec3(texelFetch(look, 4).x, texelFetch(look, 5).x, texelFetch(look, 6).x);
}

#endif
