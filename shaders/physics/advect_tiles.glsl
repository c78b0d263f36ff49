// Tiles of the gather-form advection adjoints (requires advect_sampling.glsl). The grid is cut into
// TILE³ blocks of cells; a plane's reach buffer holds tiles + 1 entries of 8 ints (the last for the
// whole plane): [0..2] the largest stencil offset o_d = b_d − c_d over the tile's interior cells,
// [4..6] the largest −o_d, each stored as REACH_BIAS + value (0: the tile has no interior cell).
#ifndef SMOKESVD_ADVECT_TILES_GLSL
#define SMOKESVD_ADVECT_TILES_GLSL

const int TILE = 8;
const int REACH_BIAS = 1 << 20;

ivec3 tileGrid() { return (n + TILE - 1) / TILE; }
int tileCount() { return tileGrid().x * tileGrid().y * tileGrid().z; }
int tileIndex(ivec3 tile) { return (tile.z * tileGrid().y + tile.y) * tileGrid().x + tile.x; }
int reachEntry(int entry) { return 8 * (plane * (tileCount() + 1) + entry); }

#endif
