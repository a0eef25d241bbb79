#version 460
// FastAtlas packing (section 4), the rule of the CPU twin fastatlas::pack_at_scale: one
// workgroup per candidate scale, all candidates at once (pass.x = 0), then one workgroup that
// finds the largest candidate that fitted and lays it out again, writing each chart's place
// (pass.x = 1; keeping every candidate's places would cost candidates x charts of memory).
// In the sorted order each box is scaled (rounded up, in integers), turned so that it is at
// least as tall as wide, and laid along one line cut into rows of capacity W - widest by an
// exclusive prefix sum (a workgroup scan per 256 boxes, carried); rows run left to right, then
// two right to left, repeated; each box rises to the front line over its columns and raises it
// by its height, one row after the other.
#extension GL_GOOGLE_include_directive : require
#include "fastatlas.glsl"

layout(local_size_x = PRISMOID_FA_WORKGROUP) in;

shared uint s_scan[PRISMOID_FA_WORKGROUP];
shared uint s_widest;
shared uint s_used;
shared uint s_last_row;

uint scaled_side(uint side, uint num) {
  uint hi, lo;
  umulExtended(side, num, hi, lo);
  uint q = (hi << 16) | (lo >> 16);  // floor(side * num / 2^16): the product stays below 2^48
  if ((lo & 0xffffu) != 0u) q += 1u;
  return max(q, 1u) + fa_push.atlas.z;
}

bool mirrored_row(uint row) { return row % 3u != 0u; }

// The box of sorted chart i at scale num / 2^16: width, height (border included), turned.
uvec3 scaled_box(uint i, uint num) {
  ivec4 b = fa_boxes[fa_charts[i]];
  uint w = uint(-b.z - b.x), h = uint(-b.w - b.y);
  bool turned = w > h;
  return uvec3(scaled_side(turned ? h : w, num), scaled_side(turned ? w : h, num), turned ? 1u : 0u);
}

void main() {
  uint lid = gl_LocalInvocationID.x;
  bool place = fa_push.pass.x == 1u;
  uint W = fa_push.atlas.x, H = fa_push.atlas.y;
  uint n = fa_state.charts.x;
  uint candidate = gl_WorkGroupID.x;
  if (place) {
    candidate = PRISMOID_FA_MAX_CANDIDATES;
    for (uint k = 0u; k < fa_push.atlas.w; ++k)
      if (fa_candidates[k].x == 1u) {
        candidate = k;
        break;
      }
    if (candidate == PRISMOID_FA_MAX_CANDIDATES) {  // nothing fits: nothing is placed or shaded
      if (lid == 0u) {
        fa_state.charts.yzw = uvec3(candidate, 0u, 0u);
        fa_state.trace.xyz = uvec3(W, 0u, 1u);
        fa_state.dispatch.xyz = uvec3(0u, 0u, 1u);
        fa_state.raster.xyz = uvec3(0u, 1u, 1u);
        fa_state.clear.xyz = uvec3((W + 15u) / 16u, (fa_history.x + 15u) / 16u, 1u);
        fa_state.copy.xyz = uvec3(0u, 0u, 1u);
        fa_history.x = 0u;
      }
      return;
    }
  }
  uint num = fa_scales[candidate];
  uint front = (place ? PRISMOID_FA_MAX_CANDIDATES : candidate) * W;
  if (lid == 0u) {
    s_widest = 0u;
    s_used = 0u;
  }
  barrier();
  for (uint i = lid; i < n; i += PRISMOID_FA_WORKGROUP) atomicMax(s_widest, scaled_box(i, num).x);
  barrier();
  uint widest = s_widest;
  bool fits = widest <= W;
  uint capacity = max(1u, W - min(widest, W));
  uint carry_row = 0u, carry_x = 0u;
  for (uint base = 0u; fits && base < n; base += PRISMOID_FA_WORKGROUP) {
    uint i = base + lid;
    bool valid = i < n;
    uvec3 box = valid ? scaled_box(i, num) : uvec3(0u);
    // Inclusive scan of the widths (Hillis-Steele).
    s_scan[lid] = box.x;
    barrier();
    for (uint step = 1u; step < PRISMOID_FA_WORKGROUP; step <<= 1u) {
      uint add = lid >= step ? s_scan[lid - step] : 0u;
      barrier();
      s_scan[lid] += add;
      barrier();
    }
    uint along = carry_x + s_scan[lid] - box.x;  // this box's start past the carried row
    uint row = carry_row + along / capacity;
    uint x = along % capacity;
    uint total = s_scan[PRISMOID_FA_WORKGROUP - 1u];
    if (i == min(n, base + PRISMOID_FA_WORKGROUP) - 1u) s_last_row = row;
    barrier();
    uint last_row = s_last_row;
    uint X = mirrored_row(row) ? W - x - box.x : x;
    uint y = 0u;
    for (uint r = carry_row; r <= last_row; ++r) {
      bool mine = valid && row == r;
      if (mine)
        for (uint c = X; c < X + box.x; ++c) y = max(y, fa_front[front + c]);
      memoryBarrierBuffer();
      barrier();
      if (mine) {
        for (uint c = X; c < X + box.x; ++c) fa_front[front + c] = y + box.y;
        atomicMax(s_used, y + box.y);
        if (place) fa_placed[fa_charts[i]] = uvec4(X, y, box.x | (box.z << 31), box.y);
      }
      memoryBarrierBuffer();
      barrier();
    }
    uint next = carry_x + total;
    carry_row += next / capacity;
    carry_x = next % capacity;
    fits = s_used <= H;
    barrier();  // s_scan and s_last_row are read above before the next chunk writes them
  }
  if (lid != 0u) return;
  if (!place) {
    fa_candidates[candidate] = uvec4(fits ? 1u : 0u, s_used, widest, 0u);
    return;
  }
  fa_state.charts.yzw = uvec3(candidate, 1u, s_used);
  // Reuse (nothing moved: this atlas is the last one, bit for bit) shades nothing.
  fa_state.trace.xyz = uvec3(W, (fa_push.image.z & PRISMOID_FA_FLAG_REUSE) != 0u ? 0u : s_used, 1u);
  fa_state.dispatch.xyz = uvec3((W + 15u) / 16u, (s_used + 15u) / 16u, 1u);
  fa_state.raster.xyz = uvec3((fa_state.counts.x + PRISMOID_FA_WORKGROUP - 1u) / PRISMOID_FA_WORKGROUP, 1u, 1u);  // the atlas raster runs
  // The clear covers this frame's rows and whatever the last frame left below them.
  uint clear_rows = max(s_used, fa_history.x);
  fa_state.copy.xyz = uvec3((W + 15u) / 16u, (fa_history.x + 15u) / 16u, 1u);  // the last frame's rows
  fa_history.x = s_used;
  fa_state.clear.xyz = uvec3((W + 15u) / 16u, (clear_rows + 15u) / 16u, 1u);
}
