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

// The 3x4 projection of a view (texels 6..8), for callers that project many points of one view.
mat3x4 camera_projection(samplerBuffer table, int view) {
  const int base = view * CAMERA_TEXELS + 6;
  return mat3x4(texelFetch(table, base), texelFetch(table, base + 1), texelFetch(table, base + 2));
}

// Pixel coordinates of grid point p under the projection rows; false if p is not in front of the camera.
bool project(mat3x4 rows, vec3 p, out vec2 pixel) {
  const vec4 h = vec4(p, 1.0);
  const float c = dot(rows[2], h);
  pixel = vec2(dot(rows[0], h), dot(rows[1], h)) / c;
  return c > 0.0;
}

bool camera_project(samplerBuffer table, int view, vec3 p, out vec2 pixel) {
  return project(camera_projection(table, view), p, pixel);
}

// An orthographic projection whose image rows are the grid's rows of voxel centres (an orbit camera with the
// volume's height in pixels): v = s - y for an integer s, and u, c independent of y, so every voxel centre
// projects onto a row of pixel centres and bilinear reads of the image never need the row below.
bool projection_in_pixel_rows(mat3x4 rows) {
  return rows[2] == vec4(0.0, 0.0, 0.0, 1.0) && rows[0].y == 0.0 && rows[1].x == 0.0 && rows[1].z == 0.0 &&
         rows[1].y == -1.0 && fract(rows[1].w) == 0.0;
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
