// Camera table (pipeline/render/view_set.h, uploadViews): 9 vec4 texels per view, grid coordinates.
//   0 origin.xyz, w = 1 for perspective    1 origin per u    2 origin per v
//   3 direction                            4 direction per u 5 direction per v
//   6..8 rows of the 3x4 projection: grid point p -> (a, b, c), pixel (u, v) = (a / c, b / c), c > 0 in front.
// Pixel coordinates (u, v) = (column + 1/2, row + 1/2); row 0 is the top of the image.
#ifndef SMOKESVD_RENDER_CAMERA_GLSL
#define SMOKESVD_RENDER_CAMERA_GLSL

const int CAMERA_TEXELS = 9;

void camera_ray(samplerBuffer table, int view, vec2 pixel, out vec3 origin, out vec3 direction) {
  const int base = view * CAMERA_TEXELS;
  origin = texelFetch(table, base).xyz + pixel.x * texelFetch(table, base + 1).xyz +
           pixel.y * texelFetch(table, base + 2).xyz;
  direction = normalize(texelFetch(table, base + 3).xyz + pixel.x * texelFetch(table, base + 4).xyz +
                        pixel.y * texelFetch(table, base + 5).xyz);
}

// Pixel coordinates of grid point p; false if p is not in front of the camera.
bool camera_project(samplerBuffer table, int view, vec3 p, out vec2 pixel) {
  const int base = view * CAMERA_TEXELS + 6;
  const vec4 h = vec4(p, 1.0);
  const float c = dot(texelFetch(table, base + 2), h);
  pixel = vec2(dot(texelFetch(table, base), h), dot(texelFetch(table, base + 1), h)) / c;
  return c > 0.0;
}

// Parameter interval [t0, t1] (t0 >= 0) where the ray lies in the box [lo, hi]; empty when t0 >= t1.
vec2 ray_box(vec3 origin, vec3 direction, vec3 lo, vec3 hi) {
  float t0 = 0.0, t1 = 3.0e38;
  for (int axis = 0; axis < 3; ++axis) {
    if (abs(direction[axis]) < 1e-12) {
      if (origin[axis] <= lo[axis] || origin[axis] >= hi[axis]) return vec2(1.0, 0.0);
      continue;
    }
    const float a = (lo[axis] - origin[axis]) / direction[axis];
    const float b = (hi[axis] - origin[axis]) / direction[axis];
    t0 = max(t0, min(a, b));
    t1 = min(t1, max(a, b));
  }
  return vec2(t0, t1);
}

#endif
