// The volume rendering integral along one ray, in GLSL and float: the
// numerical core's Riemann sum and the paper's Algorithm 3 (coupled and
// decoupled adaptive Simpson, Algorithm 2's step control), statement for
// statement as in avos/numerics/RayIntegrators.h and TransferFunction.h, so
// that the CPU core in double is this code's oracle.
//
// Inserted by vtkOpenGLAdaptiveVolumeMapper after VTK's declarations (it
// reads in_volume[0], in_depthSampler, in_windowLowerLeftCorner and
// in_inverseWindowSize); its uniforms (avos_*) are the shader property's
// custom uniforms. Every loop below is bounded: the adaptive loop by the
// core's MaximumAttempts (a ray that reaches it is reported as failed), the
// Riemann loop by ceil(D / h), the searches by log2 of the knot count.

// ---------------------------------------------------------------- the field
// Grid point value: the texel as uploaded by VTK (normalised for integer
// types) mapped back to the data's scalar, exactly for 8- and 16-bit data.
float avos_texel(ivec3 p)
{
  return texelFetch(in_volume[0], p, 0).r * avos_texelScale + avos_texelBias;
}

// Positions: where the GPU has double precision (GL_ARB_gpu_shader_fp64,
// core since OpenGL 4.0), the ray set-up, the integration variable t (step
// bounds, sample positions along the ray, the ray's length and its visible
// parts) and the samples' grid positions are in double, and only a cell's
// local coordinates, the samples' values and the sums in float. A float t
// rounds each step's bounds by up to 1.5e-5 voxel at t = 256: the core in
// float differs from the core in double by a 99th percentile of 3.3e-5 on
// Bonsai at eps 1e-4, and this shader with a double t by 1.5e-6. Elsewhere
// all in float, with those errors.
#ifdef GL_ARB_gpu_shader_fp64
#define avos_real double
#define avos_real2 dvec2
#define avos_real3 dvec3
#define avos_real3x3 dmat3
#else
#define avos_real float
#define avos_real2 vec2
#define avos_real3 vec3
#define avos_real3x3 mat3
#endif

// Trilinear interpolation at grid coordinates g, clamped onto the grid as the
// core's TrilinearVolume does (a ray clipped to the box strays by rounding).
float avos_field(avos_real3 g)
{
  avos_real3 last = avos_real3(avos_dimensions) - avos_real3(1.0);
  avos_real3 p = clamp(g, avos_real3(0.0), last);
  avos_real3 cell = min(floor(p), last - avos_real3(1.0));
  vec3 f = vec3(p - cell);
  ivec3 c = ivec3(cell);
  float v000 = avos_texel(c);
  float v100 = avos_texel(c + ivec3(1, 0, 0));
  float v010 = avos_texel(c + ivec3(0, 1, 0));
  float v110 = avos_texel(c + ivec3(1, 1, 0));
  float v001 = avos_texel(c + ivec3(0, 0, 1));
  float v101 = avos_texel(c + ivec3(1, 0, 1));
  float v011 = avos_texel(c + ivec3(0, 1, 1));
  float v111 = avos_texel(c + ivec3(1, 1, 1));
  float v00 = v000 + f.x * (v100 - v000);
  float v10 = v010 + f.x * (v110 - v010);
  float v01 = v001 + f.x * (v101 - v001);
  float v11 = v011 + f.x * (v111 - v011);
  float v0 = v00 + f.y * (v10 - v00);
  float v1 = v01 + f.y * (v11 - v01);
  return v0 + f.z * (v1 - v0);
}

// ------------------------------------------------------ the transfer function
// Pieces between consecutive knots of either function (TransferFunction's
// Piece): avos_pieceA = (start, length, opacity, opacity slope),
// avos_pieceC = (colour, jumps among the knots before this one),
// avos_pieceS = (colour slope, 0); avos_below = (colour, opacity) below the
// first knot.

// The last piece starting at or below s; -1 below the first knot or for NaN.
int avos_locate(float s)
{
  if (!(s >= avos_pieceA[0].x))
  {
    return -1;
  }
  int lo = 0;
  int hi = avos_pieceCount - 1;
  while (lo < hi)
  {
    int mid = (lo + hi + 1) / 2;
    if (avos_pieceA[mid].x <= s)
    {
      lo = mid;
    }
    else
    {
      hi = mid - 1;
    }
  }
  return lo;
}

// -ln(1 - a) with the rounding of 1 - a corrected (log1p's classic trick):
// a few ulp of relative error for small opacities too, where log(1 - a) in
// float would lose all but a few digits.
float avos_minusLog1m(float a)
{
  float u = 1.0 - a;
  if (u == 1.0)
  {
    return a;
  }
  return -log(u) * (a / (1.0 - u));
}

// The core's OpaqueExtinction: an alpha of 1 leaves 1e-17 per unit distance.
const float avos_opaqueExtinction = 40.0;

// 1 - e^{-x}, x >= 0, without the cancellation of 1 - exp(-x) near 0 (a
// Taylor polynomial below 1/32: its remainder x^5 / 120 < 3e-10 x there).
float avos_oneMinusExp(float x)
{
  if (x < 0.03125)
  {
    return x * (1.0 - x * (0.5 - x * (1.0 / 6.0 - x * (1.0 / 24.0))));
  }
  return 1.0 - exp(-x);
}

float avos_toExtinction(float value)
{
  if (avos_alphaModel == 0)
  {
    return value;
  }
  if (value >= 1.0)
  {
    return avos_opaqueExtinction / avos_unitDistance;
  }
  return min(avos_minusLog1m(value), avos_opaqueExtinction) / avos_unitDistance;
}

// The opacity function's own value at s (tau or alpha, as the model reads
// it) and the colour there: TransferFunction's GetOpacityValue and GetColor.
void avos_lookUp(float s, out float opacity, out vec3 colour)
{
  if (isnan(s))
  {
    opacity = 0.0;
    colour = vec3(0.0);
    return;
  }
  int i = avos_locate(s);
  if (i < 0)
  {
    opacity = avos_below.w;
    colour = avos_below.rgb;
    return;
  }
  vec4 a = avos_pieceA[i];
  float d = clamp(s - a.x, 0.0, a.y);
  opacity = a.z + a.w * d;
  colour = avos_pieceC[i].rgb + avos_pieceS[i].rgb * d;
}

void avos_classify(float s, out float tau, out vec3 colour)
{
  float opacity;
  avos_lookUp(s, opacity, colour);
  tau = avos_toExtinction(opacity);
}

float avos_jumpsBefore(int k)
{
  return k < avos_pieceCount ? avos_pieceC[k].w : avos_jumpsTotal;
}

// A jump of C or tau at a scalar in (lo, hi).
bool avos_hasJumpIn(float lo, float hi)
{
  int first = avos_locate(lo) + 1;
  int end = avos_locate(hi) + 1;
  if (end > 0 && avos_pieceA[end - 1].x == hi)
  {
    --end;
  }
  return end > first && avos_jumpsBefore(end) > avos_jumpsBefore(first);
}

// A kink or a jump at a scalar in (lo, hi).
bool avos_hasKnotIn(float lo, float hi)
{
  int next = avos_locate(lo) + 1;
  return next < avos_pieceCount && avos_pieceA[next].x < hi;
}

// ----------------------------------------------------------------- the ray
// Grid position at t voxel units from the ray's entry into the box.
avos_real3 avos_rayOrigin;
avos_real3 avos_rayDirection;
int avos_samples; // transfer-function evaluations of this ray

struct avos_Sample
{
  float Scalar;
  float Tau;
  vec3 Colour;
};

avos_Sample avos_sample(avos_real t)
{
  ++avos_samples;
  avos_Sample s;
  s.Scalar = avos_field(avos_rayOrigin + t * avos_rayDirection);
  avos_classify(s.Scalar, s.Tau, s.Colour);
  return s;
}

// ------------------------------------------------------ empty-space skipping
// avos_blocks holds the visibility of numerics::EmptySpaceMap's blocks
// (avos_blockSize^3 cells each, their faces' grid points included): 0 where
// the transfer function maps the block's whole value range to tau = 0. The
// trilinear field inside a block stays within that range, so such a block
// adds nothing to any ray, exactly, and the integrators see only the visible
// parts of [0, D], found as EmptySpaceMap::Segments finds them: Amanatides
// and Woo's walk over the blocks (at most Bx + By + Bz + 1 of them), each
// visible block's part widened by avos_segmentPad against rounding, parts
// that meet merged. With avos_skipping 0 the one part is [0, D].
struct avos_Walk
{
  ivec3 Block;
  ivec3 Step;
  avos_real3 Next;  // t where the walk leaves the block along each axis
  avos_real3 Delta; // t across one block along each axis
  avos_real T;      // t where the walk enters the current block
  int Left;         // blocks the walk may still visit
  bool Done;
};

avos_Walk avos_startWalk(avos_real D)
{
  avos_Walk w;
  ivec3 blocks = textureSize(avos_blocks, 0);
  avos_real size = avos_real(avos_blockSize);
  for (int a = 0; a < 3; ++a)
  {
    avos_real d = avos_rayDirection[a];
    w.Block[a] = clamp(int(floor(avos_rayOrigin[a] / size)), 0, blocks[a] - 1);
    w.Step[a] = d > avos_real(0.0) ? 1 : (d < avos_real(0.0) ? -1 : 0);
    w.Delta[a] = w.Step[a] != 0 ? size / abs(d) : avos_real(3.0e38);
    w.Next[a] = w.Step[a] > 0 ? (avos_real(w.Block[a] + 1) * size - avos_rayOrigin[a]) / d
      : (w.Step[a] < 0 ? (avos_real(w.Block[a]) * size - avos_rayOrigin[a]) / d
                       : avos_real(3.0e38));
  }
  w.T = avos_real(0.0);
  w.Left = avos_skipping != 0 ? blocks.x + blocks.y + blocks.z + 1 : 0;
  w.Done = !(D > avos_real(0.0));
  return w;
}

// The next visible part [begin, end] of [0, D] along the walk; false when
// there is none left.
bool avos_nextSegment(inout avos_Walk w, avos_real D, out avos_real begin, out avos_real end)
{
  begin = avos_real(0.0);
  end = avos_real(0.0);
  if (avos_skipping == 0)
  {
    bool first = !w.Done;
    w.Done = true;
    end = D;
    return first;
  }
  bool open = false;
  avos_real pad = avos_real(avos_segmentPad);
  while (!w.Done && w.Left > 0)
  {
    int axis = w.Next.x <= w.Next.y ? (w.Next.x <= w.Next.z ? 0 : 2)
                                    : (w.Next.y <= w.Next.z ? 1 : 2);
    avos_real exit = min(w.Next[axis], D);
    if (exit >= w.T && texelFetch(avos_blocks, w.Block, 0).r > 0.0)
    {
      avos_real b = max(w.T - pad, avos_real(0.0));
      avos_real e = min(exit + pad, D);
      if (open && b > end)
      {
        return true; // a gap: this block opens the next part
      }
      begin = open ? begin : b;
      end = open ? max(end, e) : e;
      open = true;
    }
    --w.Left;
    w.Block[axis] += w.Step[axis];
    w.T = max(w.T, exit);
    w.Next[axis] += w.Delta[axis];
    w.Done = w.Step[axis] == 0 || w.Block[axis] < 0 ||
      w.Block[axis] >= textureSize(avos_blocks, 0)[axis] || w.T >= D;
  }
  return open;
}

// The core's IntegrateRiemann (exponential form) over the visible parts:
// samples at min(i h, D) that lie inside them.
vec4 avos_riemann(avos_real D, float h, float bound)
{
  vec3 colour = vec3(0.0);
  float T = 1.0;
  int n = int(ceil(D / avos_real(h)));
  int next = 1; // the first sample index not yet taken
  avos_Walk walk = avos_startWalk(D);
  bool inside = false; // a part has been taken
  avos_real begin;
  avos_real end;
  // One loop (see avos_adaptive): each pass takes a sample or the next part.
  while (next <= n)
  {
    avos_real t1 = next == n ? D : min(avos_real(next) * avos_real(h), D);
    if (!inside || t1 > end)
    {
      if (!avos_nextSegment(walk, D, begin, end))
      {
        break;
      }
      inside = true;
      next = max(max(next, int(ceil(begin / avos_real(h)))), 1);
      continue;
    }
    float dt = float(t1 - avos_real(next - 1) * avos_real(h));
    avos_Sample s = avos_sample(t1);
    float a = avos_oneMinusExp(s.Tau * dt);
    colour += T * a * s.Colour;
    T *= 1.0 - a;
    ++next;
    if (T <= bound)
    {
      break;
    }
  }
  return vec4(colour, 1.0 - T);
}

// ------------------------------------------------ the paper's Algorithm 3
// Five equidistant samples over [U, U + K] (the core's Bracket).
struct avos_Bracket
{
  avos_real U;
  avos_real K;
  float Scale; // EstimateScale's cached value, 0 when unknown
  avos_Sample S[5];
};

void avos_fill(inout avos_Bracket b, avos_real u, avos_real k)
{
  b.U = u;
  b.K = k;
  b.Scale = 0.0;
  for (int i = 1; i < 5; ++i)
  {
    b.S[i] = avos_sample(i == 4 ? u + k : u + avos_real(0.25 * float(i)) * k);
  }
}

void avos_halve(inout avos_Bracket b)
{
  b.K *= avos_real(0.5);
  b.Scale = 0.0;
  b.S[4] = b.S[2];
  b.S[2] = b.S[1];
  b.S[1] = avos_sample(b.U + avos_real(0.25) * b.K);
  b.S[3] = avos_sample(b.U + avos_real(0.75) * b.K);
}

// Simpson's estimate assumes a smooth integrand: 15 across a jump of the
// transfer function, 5 across a kink, 1 otherwise (Bracket::EstimateScale).
float avos_estimateScale(inout avos_Bracket b)
{
  if (b.Scale > 0.0)
  {
    return b.Scale;
  }
  float lo = b.S[0].Scalar;
  float hi = lo;
  float spread = 0.0;
  for (int i = 1; i < 5; ++i)
  {
    lo = min(lo, b.S[i].Scalar);
    hi = max(hi, b.S[i].Scalar);
    spread = max(spread, abs(b.S[i].Scalar - b.S[i - 1].Scalar));
  }
  lo = max(lo - spread, avos_fieldRange.x);
  hi = min(hi + spread, avos_fieldRange.y);
  b.Scale = 1.0;
  if (lo == lo && hi == hi && lo < hi)
  {
    b.Scale = avos_hasJumpIn(lo, hi) ? 15.0 : (avos_hasKnotIn(lo, hi) ? 5.0 : 1.0);
  }
  return b.Scale;
}

// Piecewise-constant quarters integrated exactly: the step taken at h_min
// although its estimate fails (Bracket::Stable).
void avos_stable(avos_Bracket b, inout float theta, inout vec3 colour)
{
  float dt = float(0.25 * b.K);
  for (int i = 1; i < 5; ++i)
  {
    float tau = 0.5 * (b.S[i - 1].Tau + b.S[i].Tau);
    vec3 c = 0.5 * (b.S[i - 1].Colour + b.S[i].Colour);
    colour += exp(-theta) * avos_oneMinusExp(tau * dt) * c;
    theta += tau * dt;
  }
}

bool avos_allTransparent(avos_Bracket b)
{
  for (int i = 0; i < 5; ++i)
  {
    if (b.S[i].Tau != 0.0)
    {
      return false;
    }
  }
  return true;
}

// Simpson on the whole step (x) and on its halves (y) of the optical depth.
vec2 avos_inner(avos_Bracket b)
{
  float k = float(b.K);
  return vec2(k / 6.0 * (b.S[0].Tau + 4.0 * b.S[2].Tau + b.S[4].Tau),
    k / 12.0 *
      (b.S[0].Tau + 4.0 * b.S[1].Tau + 2.0 * b.S[2].Tau + 4.0 * b.S[3].Tau + b.S[4].Tau));
}

float avos_corrected(vec2 pair)
{
  return pair.y + (pair.y - pair.x) / 15.0;
}

// The same for the colour, with theta inside the step by regular Simpson
// from theta0 (Bracket::Outer).
void avos_outer(avos_Bracket b, float theta0, out vec3 whole, out vec3 halves)
{
  float k = float(b.K);
  float t[5];
  for (int i = 0; i < 5; ++i)
  {
    t[i] = b.S[i].Tau;
  }
  float theta[5];
  theta[0] = theta0;
  theta[1] = theta0 + k / 48.0 * (5.0 * t[0] + 8.0 * t[1] - t[2]);
  theta[2] = theta0 + k / 12.0 * (t[0] + 4.0 * t[1] + t[2]);
  theta[3] = theta[2] + k / 48.0 * (5.0 * t[2] + 8.0 * t[3] - t[4]);
  theta[4] = theta[2] + k / 12.0 * (t[2] + 4.0 * t[3] + t[4]);
  vec3 g[5];
  for (int i = 0; i < 5; ++i)
  {
    g[i] = t[i] > 0.0 ? b.S[i].Colour * (t[i] * exp(-theta[i])) : vec3(0.0);
  }
  whole = k / 6.0 * (g[0] + 4.0 * g[2] + g[4]);
  halves = k / 12.0 * (g[0] + 4.0 * g[1] + 2.0 * g[2] + 4.0 * g[3] + g[4]);
}

// Algorithm 2's step control (StepControl): double after two successes,
// halve on failure, within [Min, Max].
struct avos_StepControl
{
  avos_real H;
  avos_real Min;
  avos_real Max;
  bool LastSucceeded;
};

void avos_succeeded(inout avos_StepControl c)
{
  if (c.LastSucceeded)
  {
    c.H = min(avos_real(2.0) * c.H, c.Max);
  }
  c.LastSucceeded = true;
}

void avos_failed(inout avos_StepControl c)
{
  c.H = max(avos_real(0.5) * c.H, c.Min);
  c.LastSucceeded = false;
}

int avos_attempts; // accepted and rejected steps of this ray

// The paper's Algorithm 3 over the visible parts of [0, D] (IntegrateAdaptive
// over segments): the inner integral finds a step over which the optical
// depth is within its share of eps; the outer one covers that step for RGB,
// from the inner step (coupled) or its own (decoupled). The tolerance per
// unit length is spread over the parts' total length L and the steps carry
// over from one part to the next. Returns RGBA, alpha < 0 when the ray
// needed more than MaximumAttempts attempts (impossible by the argument in
// RayIntegrators.h; kept as a guard that reports instead of hanging).
vec4 avos_adaptive(avos_real D, bool coupled, float terminationDepth)
{
  avos_real L = avos_real(0.0);
  avos_real lastEnd = avos_real(0.0);
  int parts = 0;
  avos_real begin;
  avos_real end;
  avos_Walk walk = avos_startWalk(D);
  while (avos_nextSegment(walk, D, begin, end))
  {
    L += end - begin;
    lastEnd = end;
    ++parts;
  }
  if (!(L > avos_real(0.0)))
  {
    return vec4(0.0);
  }
  float hmin = max(avos_steps.y, 8.0 * 1.1920929e-7 * float(lastEnd));
  float hmax = max(avos_steps.z, hmin);
  float tolerance = 0.4 * avos_tolerance / float(L); // per unit length, inner and outer
  float maximumAttempts =
    3.0 * (ceil(float(L) / hmin) + 1.0 + float(parts)) * (ceil(log2(avos_steps.z / hmin)) + 2.0);
  avos_real h0 = avos_real(min(max(min(avos_steps.x, float(L)), hmin), hmax));
  avos_StepControl inner = avos_StepControl(h0, avos_real(hmin), avos_real(hmax), true);
  avos_StepControl outer = avos_StepControl(h0, avos_real(hmin), avos_real(hmax), true);

  avos_Bracket bin;
  avos_Bracket bout;
  vec3 colour = vec3(0.0);
  float theta = 0.0;
  // One loop over the steps of all parts, the next part taken where one
  // ends: SIMD lanes (llvmpipe, GPU warps) then iterate as long as their
  // longest ray, not as long as the sum of each part's longest one.
  walk = avos_startWalk(D);
  int part = 0; // parts begun
  avos_real t = avos_real(0.0);
  avos_real last = avos_real(0.0);
  for (;;)
  {
    if (!(t < last))
    {
      avos_real first;
      if (part == parts || !avos_nextSegment(walk, D, first, last))
      {
        break;
      }
      ++part;
      t = first;
      bin.S[0] = avos_sample(t);
      continue;
    }
    // Inner integral: the first acceptable step from t.
    float T = exp(-theta);
    avos_real remaining = last - t;
    avos_fill(bin, t, min(inner.H, remaining));
    vec2 innerPair;
    bool innerForced = false;
    for (;;)
    {
      innerPair = avos_inner(bin);
      float error = T * avos_estimateScale(bin) * abs(innerPair.y - innerPair.x) / 15.0;
      if (error <= tolerance * float(bin.K))
      {
        break;
      }
      if (bin.K <= inner.Min)
      {
        innerForced = true;
        break;
      }
      ++avos_attempts;
      avos_failed(inner);
      avos_halve(bin);
    }
    avos_real h = bin.K;
    avos_real tEnd = bin.K == remaining ? last : t + h;
    ++avos_attempts;
    float innerValue = max(avos_corrected(innerPair), 0.0);
    if (innerForced)
    {
      float thetaEnd = theta;
      avos_stable(bin, thetaEnd, colour);
      innerValue = thetaEnd - theta;
    }
    else if (!avos_allTransparent(bin))
    {
      // Outer integral over [t, tEnd].
      if (coupled)
      {
        outer.H = h;
        outer.LastSucceeded = true;
      }
      avos_real u = t;
      float thetaU = theta;
      bout.S[0] = bin.S[0];
      while (u < tEnd)
      {
        avos_real k = min(outer.H, tEnd - u);
        if (u == t && k == h)
        {
          bout = bin; // the inner step's samples, exactly
        }
        else
        {
          avos_fill(bout, u, k);
        }
        vec3 whole;
        vec3 halves;
        bool outerForced = false;
        for (;;)
        {
          avos_outer(bout, thetaU, whole, halves);
          vec3 e = abs(halves - whole) / 15.0;
          float error = avos_estimateScale(bout) * max(e.r, max(e.g, e.b));
          if (error <= tolerance * float(bout.K))
          {
            break;
          }
          if (bout.K <= outer.Min)
          {
            outerForced = true;
            break;
          }
          ++avos_attempts;
          avos_failed(outer);
          avos_halve(bout);
        }
        if (outerForced)
        {
          avos_stable(bout, thetaU, colour);
        }
        else
        {
          colour += halves + (halves - whole) / 15.0;
          thetaU += max(avos_corrected(avos_inner(bout)), 0.0);
        }
        avos_real uEnd = bout.K == tEnd - u ? tEnd : u + bout.K;
        ++avos_attempts;
        avos_succeeded(outer);
        u = uEnd;
        bout.S[0] = bout.S[4];
        if (float(avos_attempts) > maximumAttempts)
        {
          return vec4(0.0, 0.0, 0.0, -1.0);
        }
      }
    }

    theta += innerValue;
    t = tEnd;
    bin.S[0] = bin.S[4];
    avos_succeeded(inner);
    if (float(avos_attempts) > maximumAttempts)
    {
      return vec4(0.0, 0.0, 0.0, -1.0);
    }
    if (avos_earlyTermination != 0 && (t < last || part < parts) &&
      theta >= terminationDepth)
    {
      break;
    }
  }
  // Each channel lies in [0, 1 - T]: clamping only brings it closer.
  float alpha = avos_oneMinusExp(theta);
  return vec4(clamp(colour, vec3(0.0), vec3(alpha)), alpha);
}

// ------------------------------------------------------------- the cells
// Amanatides and Woo's walk over the cells the ray crosses on [tBegin,
// tEnd] (numerics::CellWalker, step for step): avos_nextCell gives the next
// cell with a part [t0, t1] (t1 > t0) of the ray inside it, false once none
// is left; at most nx + ny + nz + 3 steps.
struct avos_CellWalk
{
  ivec3 Cells; // per axis
  ivec3 Index;
  ivec3 Stride;
  avos_real3 TMax;
  avos_real3 TDelta;
  avos_real T;
  avos_real TEnd;
  int Left;
};

avos_CellWalk avos_startCells(avos_real tBegin, avos_real tEnd)
{
  avos_CellWalk w;
  w.Cells = ivec3(avos_dimensions) - ivec3(1);
  avos_real3 p = avos_rayOrigin + tBegin * avos_rayDirection;
  for (int a = 0; a < 3; ++a)
  {
    avos_real x = clamp(p[a], avos_real(0.0), avos_real(w.Cells[a]));
    w.Index[a] = min(int(x), w.Cells[a] - 1);
    avos_real d = avos_rayDirection[a];
    w.Stride[a] = d > avos_real(0.0) ? 1 : (d < avos_real(0.0) ? -1 : 0);
    w.TMax[a] = w.Stride[a] > 0 ? (avos_real(w.Index[a] + 1) - avos_rayOrigin[a]) / d
      : (w.Stride[a] < 0 ? (avos_real(w.Index[a]) - avos_rayOrigin[a]) / d : avos_real(3.0e38));
    w.TDelta[a] = w.Stride[a] != 0 ? avos_real(1.0) / abs(d) : avos_real(3.0e38);
  }
  w.T = tBegin;
  w.TEnd = tEnd;
  w.Left = tBegin < tEnd ? w.Cells.x + w.Cells.y + w.Cells.z + 3 : 0;
  return w;
}

bool avos_nextCell(inout avos_CellWalk w, out ivec3 cell, out avos_real t0, out avos_real t1)
{
  cell = w.Index;
  t0 = w.T;
  t1 = w.T;
  while (w.Left > 0 && w.T < w.TEnd)
  {
    --w.Left;
    int axis =
      w.TMax.x <= w.TMax.y ? (w.TMax.x <= w.TMax.z ? 0 : 2) : (w.TMax.y <= w.TMax.z ? 1 : 2);
    avos_real end = min(w.TMax[axis], w.TEnd);
    bool inside = end > w.T;
    cell = w.Index;
    t0 = w.T;
    t1 = end;
    w.T = max(w.T, end);
    w.Index[axis] += w.Stride[axis];
    if (w.Index[axis] < 0 || w.Index[axis] >= w.Cells[axis])
    {
      w.Left = 0;
    }
    else
    {
      w.TMax[axis] += w.TDelta[axis];
    }
    if (inside)
    {
      return true;
    }
  }
  return false;
}

// A cell's corners (x fastest), false when one is not finite (the cell is
// undefined: passed over by every method but the samplers).
bool avos_corners(ivec3 cell, out float c[8])
{
  for (int k = 0; k < 8; ++k)
  {
    c[k] = avos_texel(cell + ivec3(k & 1, (k >> 1) & 1, k >> 2));
  }
  float sum = c[0] + c[1] + c[2] + c[3] + c[4] + c[5] + c[6] + c[7];
  return !isnan(sum) && !isinf(sum);
}

// The cell's field along the ray from t0 (the cell's part starts there): the
// cubic s(u) = K.x + K.y u + K.z u^2 + K.w u^3 of the trilinear form
// A + Bx + Cy + Dz + Exy + Fxz + Gyz + Hxyz (numerics::CellCubic).
struct avos_Cubic
{
  avos_real K[4];
};

avos_Cubic avos_cellCubic(float c[8], ivec3 cell, avos_real t0)
{
  avos_real A = avos_real(c[0]);
  avos_real B = avos_real(c[1]) - A;
  avos_real C = avos_real(c[2]) - A;
  avos_real Dz = avos_real(c[4]) - A;
  avos_real E = avos_real(c[3]) - avos_real(c[2]) - B;
  avos_real F = avos_real(c[5]) - avos_real(c[4]) - B;
  avos_real G = avos_real(c[6]) - avos_real(c[4]) - C;
  avos_real H = avos_real(c[7]) - avos_real(c[6]) - avos_real(c[5]) - avos_real(c[3]) +
    avos_real(c[4]) + avos_real(c[2]) + avos_real(c[1]) - A;
  avos_real3 e = avos_rayOrigin + t0 * avos_rayDirection - avos_real3(cell);
  avos_real3 d = avos_rayDirection;
  avos_real3 g = avos_real3(B + E * e.y + F * e.z + H * e.y * e.z,
    C + E * e.x + G * e.z + H * e.x * e.z, Dz + F * e.x + G * e.y + H * e.x * e.y);
  avos_Cubic q;
  q.K[0] = A + B * e.x + C * e.y + Dz * e.z + E * e.x * e.y + F * e.x * e.z + G * e.y * e.z +
    H * e.x * e.y * e.z;
  q.K[1] = dot(d, g);
  q.K[2] = d.x * d.y * (E + H * e.z) + d.x * d.z * (F + H * e.y) + d.y * d.z * (G + H * e.x);
  q.K[3] = H * d.x * d.y * d.z;
  return q;
}

avos_real avos_at(avos_Cubic q, avos_real u)
{
  return q.K[0] + u * (q.K[1] + u * (q.K[2] + u * q.K[3]));
}

// The roots of s'(u) = 3 K3 u^2 + 2 K2 u + K1 in (0, extent), ascending
// (numerics::detail::QuadraticRoots); how many.
int avos_extrema(avos_Cubic q, avos_real extent, out avos_real roots[2])
{
  roots[0] = avos_real(0.0);
  roots[1] = avos_real(0.0);
  avos_real a = avos_real(3.0) * q.K[3];
  avos_real b = avos_real(2.0) * q.K[2];
  avos_real c = q.K[1];
  avos_real r[2];
  int n = 0;
  avos_real scale = max(max(abs(a) * extent * extent, abs(b) * extent), abs(c));
  if (scale == avos_real(0.0))
  {
    return 0;
  }
  if (abs(a) * extent * extent <= avos_real(1e-12) * scale)
  {
    if (b != avos_real(0.0))
    {
      r[n++] = -c / b;
    }
  }
  else
  {
    avos_real disc = b * b - avos_real(4.0) * a * c;
    if (disc >= avos_real(0.0))
    {
      avos_real q2 = avos_real(-0.5) * (b + (b < avos_real(0.0) ? -sqrt(disc) : sqrt(disc)));
      if (q2 != avos_real(0.0))
      {
        r[n++] = q2 / a;
        r[n++] = c / q2;
      }
    }
  }
  int count = 0;
  for (int i = 0; i < n; ++i)
  {
    if (r[i] > avos_real(0.0) && r[i] < extent)
    {
      roots[count++] = r[i];
    }
  }
  if (count == 2 && roots[0] > roots[1])
  {
    avos_real swap = roots[0];
    roots[0] = roots[1];
    roots[1] = swap;
  }
  return count;
}

// -------------------------------------- maximum and minimum intensity
// The exact extremum of the trilinear field along [0, D]
// (numerics::ExtremumAlongRay): in each cell the field along the ray is a
// cubic, whose extremum over the cell's part of the ray lies at an end or
// at a root of its derivative. A cell whose corners cannot beat the best
// value so far is passed over without its cubic, one with a non-finite
// corner too. Every cell is walked: the blocks' visibility is the composite
// integral's, not the projections'. `side` 1 for the maximum, -1 for the
// minimum; false when no finite cell lies on the ray.
bool avos_extremum(avos_real D, float side, out avos_real value)
{
  avos_real best = avos_real(-3.0e38);
  bool found = false;
  avos_CellWalk walk = avos_startCells(avos_real(0.0), D);
  ivec3 cell;
  avos_real t0;
  avos_real t1;
  while (avos_nextCell(walk, cell, t0, t1))
  {
    float c[8];
    if (!avos_corners(cell, c))
    {
      continue;
    }
    float top = side * c[0];
    float bottom = top;
    for (int k = 1; k < 8; ++k)
    {
      top = max(top, side * c[k]);
      bottom = min(bottom, side * c[k]);
    }
    if (!(avos_real(top) > best))
    {
      continue;
    }
    ++avos_samples;
    found = true;
    avos_Cubic q = avos_cellCubic(c, cell, t0);
    avos_real extent = t1 - t0;
    avos_real roots[2];
    int n = avos_extrema(q, extent, roots);
    // The ends and the roots, each value clamped to the corners' range (the
    // cubic's rounding strays beyond it).
    avos_real u[4] = avos_real[4](avos_real(0.0), extent, roots[0], roots[1]);
    for (int i = 0; i < 2 + n; ++i)
    {
      best = max(best, clamp(avos_real(side) * avos_at(q, u[i]), avos_real(bottom),
                         avos_real(top)));
    }
  }
  value = avos_real(side) * best;
  return found;
}

// The projection as VTK shows it (and vtkAdaptiveVolumeMapper): the colour at
// the extremum times the opacity function's value there clamped to [0, 1],
// that value as alpha; nothing where no finite cell lies on the ray.
vec4 avos_projection(avos_real D, bool maximum)
{
  avos_real value;
  if (!avos_extremum(D, maximum ? 1.0 : -1.0, value))
  {
    return vec4(0.0);
  }
  float opacity;
  vec3 colour;
  avos_lookUp(float(value), opacity, colour);
  float alpha = clamp(opacity, 0.0, 1.0);
  return vec4(colour * alpha, alpha);
}

// ----------------------------------------------------------- the pixel's ray
float avos_rayEntry;  // voxel units from the near plane (or -1: missed)
float avos_rayLength; // voxel units inside the box, up to the depth buffer
avos_real avos_rayExtent; // the same, as the integrators take it

// A double the mapper split into float hi + lo (hi alone without fp64).
avos_real avos_join(float hi, float lo)
{
  return avos_real(hi) + avos_real(lo);
}

avos_real3 avos_join(vec3 hi, vec3 lo)
{
  return avos_real3(hi) + avos_real3(lo);
}

// The ray through this fragment's pixel centre from the near plane to the
// depth buffer (as vtkAdaptiveVolumeMapper casts it), clipped to the grid's
// box [0, n - 1]. False when it misses the box. Its points are affine in
// NDC x, y on any plane of constant depth (a camera's homogeneous w depends
// on the depth alone), so the mapper gives, in double, the coefficients of
// the point on the plane through the volume's centre and of the near-to-far
// vector: even in float, positions then carry errors of the volume's size,
// not of the camera's distance. The point at depth d lies at the fraction
// w_f d / (w_n (1 - d) + w_f d) of the way from the near to the far plane.
bool avos_setUpRay()
{
  // The window's size is an integer: exact from its float inverse.
  avos_real2 size = floor(avos_real2(1.0) / avos_real2(in_inverseWindowSize) + avos_real2(0.5));
  avos_real2 window = (avos_real2(gl_FragCoord.xy) - avos_real2(in_windowLowerLeftCorner)) / size;
  avos_real2 ndc = avos_real(2.0) * window - avos_real2(1.0);
  avos_real depth = avos_real(texture2D(in_depthSampler, vec2(window)).x);
  avos_real3 centre = avos_join(avos_centre[0], avos_centreLo[0]) +
    ndc.x * avos_join(avos_centre[1], avos_centreLo[1]) +
    ndc.y * avos_join(avos_centre[2], avos_centreLo[2]);
  avos_real3 span = avos_join(avos_span[0], avos_spanLo[0]) +
    ndc.x * avos_join(avos_span[1], avos_spanLo[1]) +
    ndc.y * avos_join(avos_span[2], avos_spanLo[2]);
  avos_real3x3 gridToVoxel = avos_real3x3(avos_gridToVoxel) + avos_real3x3(avos_gridToVoxelLo);
  avos_real total = length(gridToVoxel * span);
  avos_real wn = avos_join(avos_planeW.x, avos_planeWLo.x);
  avos_real wf = avos_join(avos_planeW.y, avos_planeWLo.y);
  avos_real fraction = wf * depth / (wn * (avos_real(1.0) - depth) + wf * depth);
  avos_rayEntry = -1.0;
  avos_rayLength = 0.0;
  if (!(total > avos_real(0.0)))
  {
    return false;
  }
  avos_real3 direction = span / total;
  // u: voxel units from the centre plane, which lies tc from the near plane.
  avos_real tc = avos_join(avos_centreFraction.x, avos_centreFraction.y) * total;
  avos_real u0 = -tc;
  avos_real u1 = fraction * total - tc;
  avos_real3 last = avos_real3(avos_dimensions) - avos_real3(1.0);
  for (int a = 0; a < 3; ++a)
  {
    if (direction[a] == avos_real(0.0))
    {
      if (centre[a] < avos_real(0.0) || centre[a] > last[a])
      {
        return false;
      }
      continue;
    }
    avos_real ua = -centre[a] / direction[a];
    avos_real ub = (last[a] - centre[a]) / direction[a];
    u0 = max(u0, min(ua, ub));
    u1 = min(u1, max(ua, ub));
  }
  if (!(u1 > u0))
  {
    return false;
  }
  avos_rayOrigin = centre + u0 * direction;
  avos_rayDirection = direction;
  avos_rayEntry = float(tc + u0);
  avos_rayExtent = u1 - u0;
  avos_rayLength = float(avos_rayExtent);
  return true;
}

vec4 avos_result;

// Casts this fragment's ray with the chosen method into avos_result
// (premultiplied RGBA over black).
void avos_castRay()
{
  avos_samples = 0;
  avos_attempts = 0;
  avos_result = vec4(0.0);
  if (!avos_setUpRay())
  {
    return;
  }
  // What the rest of a ray can add to any channel is at most T max(1, max C).
  float budget = 0.2 * avos_tolerance / max(1.0, avos_maximumColour);
  if (avos_blend != 0)
  {
    avos_result = avos_projection(avos_rayExtent, avos_blend == 1);
  }
  else if (avos_method == 0)
  {
    float bound = avos_earlyTermination != 0 ? budget : 0.0;
    avos_result = avos_riemann(avos_rayExtent, avos_steps.w, bound);
  }
  else
  {
    avos_result = avos_adaptive(avos_rayExtent, avos_method == 1, -log(budget));
  }
  // Mesa's llvmpipe ends the loops of a shader invocation, silently, once
  // they have run 65535 iterations in all (gallivm's loop limiter, counted
  // per group of SIMD lanes; an exhausted limiter still lets a loop run
  // once). A loop that must run twice (avos_two is 2) and did not means this
  // ray was cut short: it is reported as failed (alpha -1), as a ray beyond
  // MaximumAttempts is, never shown as a value.
  int trips = 0;
  for (int i = 0; i < avos_two; ++i)
  {
    ++trips;
  }
  bool complete = trips == 2;
  if (!complete)
  {
    avos_result = vec4(0.0, 0.0, 0.0, -1.0);
  }
}

// The quantity the validation image (RenderToImage's float depth image)
// receives: 1..4 RGBA, 5 the ray's entry, 6 its length, 7 its samples.
void avos_writeQuantity()
{
  if (avos_quantity == 0)
  {
    return;
  }
  float v = avos_quantity <= 4 ? avos_result[avos_quantity - 1]
                               : (avos_quantity == 5 ? avos_rayEntry
                                                     : (avos_quantity == 6 ? avos_rayLength
                                                                           : float(avos_samples)));
  // Alpha 1: the blend (one, one minus source alpha) keeps the value alone.
  gl_FragData[1] = vec4(v, v, v, 1.0);
}
