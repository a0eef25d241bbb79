// The field an interval pass integrates over one cell, as both backends read it: for emission
// (and marching) the transfer function's normalized scalar, linear from the point scalars or
// constant per cell; for optical depth sigma, linear from the point extinction or constant.
// The caller declares `frame`, cell_sigma and cell_scalar.
#ifndef PRISMOID_CELL_FIELD_GLSL
#define PRISMOID_CELL_FIELD_GLSL

// `value`: the point field at the corners (per point only). Writes the field at the corners
// and returns the largest extinction the cell can have: cells returning 0 add nothing to an
// optical depth and are not drawn (emission draws every cell: the transfer function decides).
float cell_field(uint cell, bool emission, bool per_point, float value[4], out float field[4]) {
  if (emission) {
    // x = value * scale + offset, both rounded from double once (volume::scalar_mapping): a
    // range far wider than the data or far from zero still maps it without overflow.
    float scale = frame.transfer.x, offset = frame.transfer.y;
    float cell_x = per_point ? 0.0 : cell_scalar[cell] * scale + offset;
    for (int i = 0; i < 4; ++i) field[i] = per_point ? value[i] * scale + offset : cell_x;
    return 1.0;
  }
  if (per_point) {
    for (int i = 0; i < 4; ++i) field[i] = value[i];
    return max(max(value[0], value[1]), max(value[2], value[3]));
  }
  float sigma = cell_sigma[cell];
  for (int i = 0; i < 4; ++i) field[i] = sigma;
  return sigma;
}

#endif
