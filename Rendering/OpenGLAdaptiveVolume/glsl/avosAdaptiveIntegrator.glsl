// What a ray shows, in GLSL, statement for statement as the numerical core
// computes it, so that the CPU core in double is this code's oracle: the
// volume rendering integral by the core's Riemann sum and the paper's
// Algorithm 3 (coupled and decoupled adaptive Simpson, Algorithm 2's step
// control; RayIntegrators.h), their samples lit (Shading.h) and scaled by
// gradient opacity (GradientOpacity.h); the piecewise method
// (PiecewiseIntegrator.h); the exact maximum and minimum intensity
// projections (Extremum.h); the additive and average projections
// (Accumulation.h); over the four fields of point and cell scalars
// (Volume.h), the empty-space blocks (EmptySpace.h), clipping planes and
// cropping (ClipRegion).
//
// Inserted by vtkOpenGLAdaptiveVolumeMapper after VTK's declarations (it
// reads in_volume[0], in_depthSampler, in_windowLowerLeftCorner and
// in_inverseWindowSize); its uniforms (avos_*) are the shader property's
// custom uniforms. Every loop below is bounded: the adaptive loop by the
// core's MaximumAttempts (a ray that reaches it is reported as failed), the
// Riemann loop by ceil(D / h), the walks by the cells and pieces of the ray,
// the searches by log2 of the knot count.

// ---------------------------------------------------------------- the field
// Grid point value: the texel's channel avos_channel (of several
// components, the one being read) as uploaded by VTK (normalised for
// integer types, scaled onto [0, 1] for 32- and 64-bit ones) mapped back to
// the data's scalar (the mapper's TexelMap), rounded to the integer it was
// for integer data: exact for them.
int avos_channel; // avos_component, or each of a mixture's in turn (avos_sample)

float avos_texel(ivec3 p)
{
  float v = texelFetch(in_volume[0], p, 0)[avos_channel] * avos_texelScale + avos_texelBias;
  return avos_texelRound != 0 ? round(v) : v;
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
#ifdef AVOS_DOUBLE_PRECISION // defined by the mapper with the extension
#define avos_real double
#define AVOS_DOUBLE(x) x##LF // a literal in double
#define avos_ldexp(x, k) ldexp(x, k)
#define avos_real2 dvec2
#define avos_real3 dvec3
#define avos_real3x3 dmat3
#else
#define avos_real float
#define AVOS_DOUBLE(x) x
#define avos_ldexp(x, k) ((x) * exp2(float(k))) // (ldexp: GLSL 4.00)
#define avos_real2 vec2
#define avos_real3 vec3
#define avos_real3x3 mat3
#endif

// The field the scalars make (avos_fieldKind, as the CPU mapper's
// engine::ScalarField): 0 point scalars, trilinear; 1 point scalars, each
// point's value on the part of the box nearest to it (nearest); 2 cell
// scalars, constant on each cell (nearest); 3 cell scalars, trilinear
// between the cells' centres, clamped at the outer half cells (linear; the
// texture then holds a texel per cell, as VTK uploads cell scalars). Every
// method walks the cells of the walk grid, the point grid refined by
// avos_walkScale (2 for fields 1 and 3, else 1; numerics'
// CellConstantVolume and CellCentredVolume): the field is trilinear on each
// of them, with the corners avos_cornerValues gives, and a ray's t is the
// same on both grids.
ivec3 avos_walkCells()
{
  return avos_walkScale * (ivec3(avos_dimensions) - ivec3(1));
}

// Along one axis of field 3, walk cell i reads the cells lo and hi (clamped
// into the box); at its corners 0 and 1 the field holds lo + w (hi - lo)
// with w = weights (CellCentredVolume::Weights: the mean of the cells beside
// a face between centres, a cell's own value at its centre).
void avos_centredAxis(int i, int last, out int lo, out int hi, out vec2 weights)
{
  int m = i / 2;
  bool centreLast = (i & 1) == 0; // corner 1 at a centre, corner 0 on a face
  lo = centreLast ? max(m - 1, 0) : m;
  hi = centreLast ? m : min(m + 1, last);
  weights = centreLast ? vec2(0.5, 1.0) : vec2(0.0, 0.5);
}

// The bilinear values of a face's four texels at its corners (x fastest),
// weights wx, wy per axis.
vec4 avos_bilinear(float v00, float v10, float v01, float v11, vec2 wx, vec2 wy)
{
  vec2 y0 = vec2(v00) + wx * (v10 - v00); // along x at y = lo
  vec2 y1 = vec2(v01) + wx * (v11 - v01);
  vec2 lo = y0 + wy.x * (y1 - y0);
  vec2 hi = y0 + wy.y * (y1 - y0);
  return vec4(lo, hi);
}

void avos_cornerValues(ivec3 cell, out float c[8])
{
  if (avos_fieldKind == 0)
  {
    c[0] = avos_texel(cell);
    c[1] = avos_texel(cell + ivec3(1, 0, 0));
    c[2] = avos_texel(cell + ivec3(0, 1, 0));
    c[3] = avos_texel(cell + ivec3(1, 1, 0));
    c[4] = avos_texel(cell + ivec3(0, 0, 1));
    c[5] = avos_texel(cell + ivec3(1, 0, 1));
    c[6] = avos_texel(cell + ivec3(0, 1, 1));
    c[7] = avos_texel(cell + ivec3(1, 1, 1));
    return;
  }
  if (avos_fieldKind != 3)
  {
    // Walk cell i of the refined grid, [i / 2, (i + 1) / 2], is nearest to
    // point (i + 1) / 2; a cell of field 2 is its own texel.
    // (Fixed loops are written out here: llvmpipe counts their iterations
    // against its limit, avos_castRay.)
    float v = avos_texel(avos_fieldKind == 1 ? (cell + ivec3(1)) / 2 : cell);
    c[0] = v;
    c[1] = v;
    c[2] = v;
    c[3] = v;
    c[4] = v;
    c[5] = v;
    c[6] = v;
    c[7] = v;
    return;
  }
  ivec3 last = ivec3(avos_dimensions) - ivec3(2);
  ivec3 lo;
  ivec3 hi;
  vec2 wx;
  vec2 wy;
  vec2 wz;
  avos_centredAxis(cell.x, last.x, lo.x, hi.x, wx);
  avos_centredAxis(cell.y, last.y, lo.y, hi.y, wy);
  avos_centredAxis(cell.z, last.z, lo.z, hi.z, wz);
  float v000 = avos_texel(lo);
  float v100 = avos_texel(ivec3(hi.x, lo.y, lo.z));
  float v010 = avos_texel(ivec3(lo.x, hi.y, lo.z));
  float v110 = avos_texel(ivec3(hi.x, hi.y, lo.z));
  float v001 = avos_texel(ivec3(lo.x, lo.y, hi.z));
  float v101 = avos_texel(ivec3(hi.x, lo.y, hi.z));
  float v011 = avos_texel(ivec3(lo.x, hi.y, hi.z));
  float v111 = avos_texel(hi);
  // Per z side: the bilinear values at the four (x, y) corners.
  vec4 front = avos_bilinear(v000, v100, v010, v110, wx, wy);
  vec4 back = avos_bilinear(v001, v101, v011, v111, wx, wy);
  vec4 zl = front + wz.x * (back - front);
  vec4 zh = front + wz.y * (back - front);
  c[0] = zl.x;
  c[1] = zl.y;
  c[2] = zl.z;
  c[3] = zl.w;
  c[4] = zh.x;
  c[5] = zh.y;
  c[6] = zh.z;
  c[7] = zh.w;
}

// The walk cell holding point-grid coordinates g and g's coordinates f in
// it, clamped onto the box as the core's volumes clamp (a ray clipped to the
// box strays by rounding).
void avos_cellAt(avos_real3 g, out ivec3 cell, out vec3 f)
{
  avos_real3 last = avos_real3(avos_walkCells());
  avos_real3 p = clamp(g * avos_real(avos_walkScale), avos_real3(0.0), last);
  avos_real3 lower = min(floor(p), last - avos_real3(1.0));
  cell = ivec3(lower);
  f = vec3(p - lower);
}

// The trilinear form of a cell's corners c at its coordinates f.
float avos_trilinear(float c[8], vec3 f)
{
  float v00 = c[0] + f.x * (c[1] - c[0]);
  float v10 = c[2] + f.x * (c[3] - c[2]);
  float v01 = c[4] + f.x * (c[5] - c[4]);
  float v11 = c[6] + f.x * (c[7] - c[6]);
  float v0 = v00 + f.y * (v10 - v00);
  float v1 = v01 + f.y * (v11 - v01);
  return v0 + f.z * (v1 - v0);
}

// ------------------------------------------------------ the transfer function
// Pieces between consecutive knots of either function of a transfer
// function (TransferFunction's Piece): avos_pieceA = (start, length,
// opacity, opacity slope), avos_pieceC = (colour, jumps among its knots
// before this one), avos_pieceS = (colour slope, 0). Function f's pieces are
// avos_piece*[avos_fnFirst[f], avos_fnFirst[f] + avos_fnCount[f]), its
// colour and opacity below its first knot avos_fnBelow[f], its unit
// distance avos_fnUnit[f], its jump count avos_fnJumpsTotal[f]. Function 0
// is the one medium's. For a mixture (numerics::MixtureTransferFunction)
// the mapper defines AVOS_MIXTURE, its number of components, and
// AVOS_MIX_KIND: 1, independent components, component k through function k
// with weight avos_mixWeight[k]; 2, the colour of s_0 and the opacity of
// s_1 through function 0; 3, the colour (s_0, s_1, s_2) times avos_mixScale
// and the opacity of s_3 through function 0. Only the code of that mixture
// is compiled (the mapper's directives; a change rebuilds the shader):
// llvmpipe runs both sides of a branch, so a sample of one medium would
// otherwise pay four reads of the cell and four transfer-function searches,
// and a mixture the code of the others.

// The last piece of function f starting at or below s; -1 below its first
// knot or for NaN. A binary search; for a mixture, whose every sample
// searches each component's function, one of a fixed 12 steps written out
// (a function has at most 4096 pieces: the mapper's UniformStorageProblem),
// as llvmpipe counts each iteration of a loop it keeps against its limit
// (see avos_castRay).
#define AVOS_LOCATE_IN_STEP(k)                                                                     \
  next = lo + k;                                                                                   \
  lo = next < count && avos_pieceA[first + min(next, count - 1)].x <= s ? next : lo;
int avos_locateIn(int f, float s)
{
  int first = avos_fnFirst[f];
  if (!(s >= avos_pieceA[first].x))
  {
    return -1;
  }
  int count = avos_fnCount[f];
  int lo = 0;
#ifdef AVOS_MIXTURE
  int next;
  AVOS_LOCATE_IN_STEP(2048)
  AVOS_LOCATE_IN_STEP(1024)
  AVOS_LOCATE_IN_STEP(512)
  AVOS_LOCATE_IN_STEP(256)
  AVOS_LOCATE_IN_STEP(128)
  AVOS_LOCATE_IN_STEP(64)
  AVOS_LOCATE_IN_STEP(32)
  AVOS_LOCATE_IN_STEP(16)
  AVOS_LOCATE_IN_STEP(8)
  AVOS_LOCATE_IN_STEP(4)
  AVOS_LOCATE_IN_STEP(2)
  AVOS_LOCATE_IN_STEP(1)
#else
  int hi = count - 1;
  while (lo < hi)
  {
    int mid = (lo + hi + 1) / 2;
    if (avos_pieceA[first + mid].x <= s)
    {
      lo = mid;
    }
    else
    {
      hi = mid - 1;
    }
  }
#endif
  return first + lo;
}

int avos_locate(float s)
{
  return avos_locateIn(0, s);
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

float avos_toExtinctionIn(int f, float value)
{
  if (avos_alphaModel == 0)
  {
    return value;
  }
  if (value >= 1.0)
  {
    return avos_opaqueExtinction / avos_fnUnit[f];
  }
  return min(avos_minusLog1m(value), avos_opaqueExtinction) / avos_fnUnit[f];
}

float avos_toExtinction(float value)
{
  return avos_toExtinctionIn(0, value);
}

// Function f's own opacity value at s (tau or alpha, as the model reads
// it) and the colour there on piece i (avos_locateIn's; -1: below the first
// knot).
void avos_pieceAtIn(int f, int i, float s, out float opacity, out vec3 colour)
{
  if (i < 0)
  {
    opacity = avos_fnBelow[f].w;
    colour = avos_fnBelow[f].rgb;
    return;
  }
  vec4 a = avos_pieceA[i];
  float d = clamp(s - a.x, 0.0, a.y);
  opacity = a.z + a.w * d;
  colour = avos_pieceC[i].rgb + avos_pieceS[i].rgb * d;
}

void avos_pieceAt(int i, float s, out float opacity, out vec3 colour)
{
  avos_pieceAtIn(0, i, s, opacity, colour);
}

// The same at s: TransferFunction's GetOpacityValue and GetColor.
void avos_lookUpIn(int f, float s, out float opacity, out vec3 colour)
{
  if (isnan(s))
  {
    opacity = 0.0;
    colour = vec3(0.0);
    return;
  }
  avos_pieceAtIn(f, avos_locateIn(f, s), s, opacity, colour);
}

void avos_lookUp(float s, out float opacity, out vec3 colour)
{
  avos_lookUpIn(0, s, opacity, colour);
}

void avos_classifyIn(int f, float s, out float tau, out vec3 colour)
{
  float opacity;
  avos_lookUpIn(f, s, opacity, colour);
  tau = avos_toExtinctionIn(f, opacity);
}

void avos_classify(float s, out float tau, out vec3 colour)
{
  avos_classifyIn(0, s, tau, colour);
}

#ifdef AVOS_MIXTURE
// MixtureTransferFunction::Classify: tau and the colour of the medium at
// the components' values s. (The loops over the components here and in
// avos_sample and avos_estimateScale are written out, as avos_locateIn's.)
#define AVOS_MIX_ADD(k)                                                                            \
  if (avos_mixWeight[k] > 0.0)                                                                     \
  {                                                                                                \
    float t;                                                                                       \
    vec3 c;                                                                                        \
    avos_classifyIn(k, s[k], t, c);                                                                \
    tau += avos_mixWeight[k] * t;                                                                  \
    emission += (avos_mixWeight[k] * t) * c;                                                       \
  }
void avos_classifyMixture(vec4 s, out float tau, out vec3 colour)
{
  tau = 0.0;
  colour = vec3(0.0);
#if AVOS_MIX_KIND == 1
  vec3 emission = vec3(0.0);
  AVOS_MIX_ADD(0)
  AVOS_MIX_ADD(1)
#if AVOS_MIXTURE > 2
  AVOS_MIX_ADD(2)
#endif
#if AVOS_MIXTURE > 3
  AVOS_MIX_ADD(3)
#endif
  if (tau > 0.0)
  {
    colour = emission / tau;
  }
#elif AVOS_MIX_KIND == 2
  if (!isnan(s[0]))
  {
    float opacity;
    vec3 c;
    avos_classifyIn(0, s[1], tau, c);
    avos_lookUpIn(0, s[0], opacity, colour);
  }
#else
  vec3 rgb = s.xyz * avos_mixScale;
  if (!isnan(rgb.x + rgb.y + rgb.z))
  {
    vec3 c;
    avos_classifyIn(0, s[3], tau, c);
    colour = rgb;
  }
#endif
}
#endif

float avos_jumpsBeforeIn(int f, int k)
{
  return k < avos_fnFirst[f] + avos_fnCount[f] ? avos_pieceC[k].w : avos_fnJumpsTotal[f];
}

// A jump of function f's C or tau at a scalar in (lo, hi).
bool avos_hasJumpInOf(int f, float lo, float hi)
{
  int first = avos_locateIn(f, lo);
  int end = avos_locateIn(f, hi);
  first = first < 0 ? avos_fnFirst[f] : first + 1;
  end = end < 0 ? avos_fnFirst[f] : end + 1;
  if (end > avos_fnFirst[f] && avos_pieceA[end - 1].x == hi)
  {
    --end;
  }
  return end > first && avos_jumpsBeforeIn(f, end) > avos_jumpsBeforeIn(f, first);
}

// A kink or a jump of function f at a scalar in (lo, hi).
bool avos_hasKnotInOf(int f, float lo, float hi)
{
  int next = avos_locateIn(f, lo);
  next = next < 0 ? avos_fnFirst[f] : next + 1;
  return next < avos_fnFirst[f] + avos_fnCount[f] && avos_pieceA[next].x < hi;
}

// ----------------------------------------------------------------- the ray
// Grid position at t voxel units from the ray's entry into the box.
avos_real3 avos_rayOrigin;
avos_real3 avos_rayDirection;
avos_real3 avos_walkOrigin; // the ray on the walk grid (avos_walkScale): the same t
avos_real3 avos_walkDirection;
vec3 avos_toViewer; // shading: the unit world direction towards the viewer
int avos_samples; // transfer-function evaluations of this ray

struct avos_Sample
{
  float Scalar;
#ifdef AVOS_MIXTURE
  vec4 Scalars; // the components'
#endif
  float Tau;
  vec3 Colour;
};

// ------------------------------------------------------------------ shading
// numerics::ShadingModel's lit colour on numbers (Shading.h, LitColourOf),
// for the sampled methods (avos_shade 1): Blinn-Phong with the property's
// coefficients avos_shading = (ka, kd, ks, specular power), two-sided or
// not, the renderer's lights (avos_lightCount of 8 slots: avos_lightPosition
// xyz the unit direction towards a directional light or a positional
// light's position, w 1 when positional; diffuse and specular colours times
// intensity; avos_lightAttenuation the attenuation values and the cosine of
// a spot's cone angle, below -1 for no cone; avos_lightAxis a spot's unit
// axis and exponent), the exact gradient of the trilinear field mapped
// to world space by the normal matrix (avos_normalRows, its rows), positions
// by the grid-to-world map (avos_gridToWorld, the rows of its affine part),
// the viewer along the ray, ambient light alone where the gradient
// vanishes, each channel clamped to [0, 1].

vec3 avos_toWorld(vec4 rows[3], vec4 p)
{
  return vec3(dot(rows[0], p), dot(rows[1], p), dot(rows[2], p));
}

// The gradient of the trilinear form of a cell's corners c at its
// coordinates f, in walk-grid units (TrilinearVolume::Gradient; the point
// grid's for field 0, the only one shaded or scaled by gradient opacity).
vec3 avos_trilinearGradient(float c[8], vec3 f)
{
  float dx00 = c[1] - c[0];
  float dx10 = c[3] - c[2];
  float dx01 = c[5] - c[4];
  float dx11 = c[7] - c[6];
  float gx = mix(mix(dx00, dx10, f.y), mix(dx01, dx11, f.y), f.z);
  float x00 = c[0] + f.x * dx00;
  float x10 = c[2] + f.x * dx10;
  float x01 = c[4] + f.x * dx01;
  float x11 = c[6] + f.x * dx11;
  float gy = mix(x10 - x00, x11 - x01, f.z);
  float gz = mix(x01, x11, f.y) - mix(x00, x10, f.y);
  return vec3(gx, gy, gz);
}

float avos_facing(float c)
{
  return avos_twoSided != 0 ? abs(c) : max(c, 0.0);
}

// x^p for x >= 0, 0 at x = 0 (as VTK's mappers skip a facing term of 0).
float avos_facingPower(float x, float p)
{
  return x > 0.0 ? pow(x, p) : 0.0;
}

// Light slot i's terms at world position x for the unit normal n and the
// viewer towards v: its attenuated f(n.l) into diffuse, f(n.h)^p into
// specular.
void avos_light(int i, vec3 x, vec3 n, vec3 v, inout vec3 diffuse, inout vec3 specular)
{
  vec4 at = avos_lightPosition[i];
  vec3 l = at.xyz;
  float attenuation = 1.0;
  if (at.w != 0.0)
  {
    vec3 towards = at.xyz - x;
    float squared = dot(towards, towards);
    float inverse = squared > 0.0 ? inversesqrt(squared) : 0.0;
    vec4 a = avos_lightAttenuation[i];
    l = towards * inverse;
    attenuation = squared > 0.0 ? 1.0 / (a.x + a.y * (squared * inverse) + a.z * squared) : 0.0;
    if (a.w >= -1.0)
    {
      float cone = -dot(l, avos_lightAxis[i].xyz);
      attenuation *= cone >= a.w ? avos_facingPower(cone, avos_lightAxis[i].w) : 0.0;
    }
  }
  vec3 halfway = l + v;
  float halfLength = length(halfway);
  float nh = halfLength > 0.0 ? avos_facing(clamp(dot(n, halfway / halfLength), -1.0, 1.0)) : 0.0;
  diffuse += (attenuation * avos_facing(clamp(dot(n, l), -1.0, 1.0))) * avos_lightDiffuse[i].rgb;
  specular += (attenuation * avos_facingPower(nh, avos_shading.w)) * avos_lightSpecular[i].rgb;
}

// The colour of the sample at grid position g, whose world-space gradient
// is `gradient`, lit. The first light is written out, a loop takes the
// others: llvmpipe counts a loop's iterations against its limit
// (avos_castRay), and a loop over the headlight alone cut 9.4 % of Bonsai's
// shaded coupled rays at eps 1e-3 short (7.6 % now, the adaptive rule's own
// steps); all eight slots written out made the shader take four times as
// long to compile.
vec3 avos_lit(vec3 colour, vec3 gradient, avos_real3 g)
{
  vec3 ambient = avos_shading.x * colour;
  float squared = dot(gradient, gradient);
  if (!(squared > 0.0) || isinf(squared))
  {
    return clamp(ambient, vec3(0.0), vec3(1.0));
  }
  vec3 n = gradient * inversesqrt(squared);
  vec3 x = avos_toWorld(avos_gridToWorld, vec4(vec3(g), 1.0));
  vec3 v = avos_toViewer;
  vec3 diffuse = vec3(0.0);
  vec3 specular = vec3(0.0);
  if (avos_lightCount > 0)
  {
    avos_light(0, x, n, v, diffuse, specular);
  }
  for (int i = 1; i < avos_lightCount; ++i)
  {
    avos_light(i, x, n, v, diffuse, specular);
  }
  vec3 value = ambient + avos_shading.y * diffuse * colour + avos_shading.z * specular;
  return clamp(value, vec3(0.0), vec3(1.0));
}

// ----------------------------------------------------- gradient opacity
// The sampled methods' gradient opacity (avos_gradientOpacity 1;
// numerics::GradientOpacity): a sample's extinction times G(|g|), |g| the
// length of the world-space gradient (scalar units per world unit), G the
// property's gradient opacity function clamped to [0, 1], held as its
// pieces avos_gPiece = (start, length, value, slope) (avos_gCount of them,
// at most 128) and avos_gBelow below the first. The last piece starting at
// or below |g| by a binary search of 7 steps, written out.
#define AVOS_G_STEP(k)                                                                             \
  next = lo + k;                                                                                   \
  lo = next < avos_gCount && avos_gPiece[min(next, avos_gCount - 1)].x <= g ? next : lo;
float avos_gradientFactor(float g)
{
  if (!(g >= avos_gPiece[0].x))
  {
    return clamp(avos_gBelow, 0.0, 1.0);
  }
  int lo = 0;
  int next;
  AVOS_G_STEP(64)
  AVOS_G_STEP(32)
  AVOS_G_STEP(16)
  AVOS_G_STEP(8)
  AVOS_G_STEP(4)
  AVOS_G_STEP(2)
  AVOS_G_STEP(1)
  vec4 p = avos_gPiece[lo];
  return clamp(p.z + p.w * clamp(g - p.x, 0.0, p.y), 0.0, 1.0);
}

#ifdef AVOS_MIXTURE
#define AVOS_MIX_READ(k)                                                                           \
  avos_channel = k;                                                                                \
  avos_cornerValues(cell, c);                                                                      \
  s.Scalars[k] = avos_trilinear(c, f);
#endif

// The sample at t: its scalar, extinction (times G with gradient opacity)
// and colour (lit when shading).
avos_Sample avos_sample(avos_real t)
{
  ++avos_samples;
  avos_Sample s;
  avos_real3 g = avos_rayOrigin + t * avos_rayDirection;
  ivec3 cell;
  vec3 f;
  avos_cellAt(g, cell, f);
  float c[8];
#ifdef AVOS_MIXTURE
  // Each component's field (its channel in turn), the medium of them all
  // (unshaded, without gradient opacity: the mapper refuses those).
  s.Scalars = vec4(0.0);
  AVOS_MIX_READ(0)
  AVOS_MIX_READ(1)
#if AVOS_MIXTURE > 2
  AVOS_MIX_READ(2)
#endif
#if AVOS_MIXTURE > 3
  AVOS_MIX_READ(3)
#endif
  s.Scalar = s.Scalars[0];
  avos_classifyMixture(s.Scalars, s.Tau, s.Colour);
  return s;
#endif
  avos_cornerValues(cell, c);
  s.Scalar = avos_trilinear(c, f);
  avos_classify(s.Scalar, s.Tau, s.Colour);
  if ((avos_shade != 0 || avos_gradientOpacity != 0) && s.Tau > 0.0)
  {
    vec3 gradient = avos_toWorld(avos_normalRows, vec4(avos_trilinearGradient(c, f), 0.0));
    if (avos_gradientOpacity != 0)
    {
      s.Tau *= avos_gradientFactor(length(gradient));
    }
    if (avos_shade != 0)
    {
      s.Colour = avos_lit(s.Colour, gradient, g);
    }
  }
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
  // avos_nextPart's state: the visible part taken from the blocks' walk
  // and the kept part (of avos_kept) it is cut by.
  avos_real2 Visible;
  bool HasVisible;
  int Kept;
};

// The kept parts of the ray (cropping: at most 7, sorted, disjoint; else
// [0, D]), set by avos_setUpRay.
avos_real2 avos_kept[7];
int avos_keptCount;

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
  w.Visible = avos_real2(0.0);
  w.HasVisible = false;
  w.Kept = 0;
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

// The next visible and kept part [begin, end] of [0, D]: the blocks' parts
// (avos_nextSegment) cut by the kept parts (numerics::ClipRegion::
// Intersect), `part` the kept part it lies in; false when none is left.
bool avos_nextPart(inout avos_Walk w, avos_real D, out avos_real begin, out avos_real end,
  out int part)
{
  begin = avos_real(0.0);
  end = avos_real(0.0);
  part = w.Kept;
  while (w.Kept < avos_keptCount)
  {
    if (!w.HasVisible)
    {
      if (!avos_nextSegment(w, D, w.Visible.x, w.Visible.y))
      {
        return false;
      }
      w.HasVisible = true;
    }
    avos_real2 kept = avos_kept[w.Kept];
    begin = max(w.Visible.x, kept.x);
    end = min(w.Visible.y, kept.y);
    part = w.Kept;
    if (w.Visible.y < kept.y)
    {
      w.HasVisible = false;
    }
    else
    {
      ++w.Kept;
    }
    if (begin < end)
    {
      return true;
    }
  }
  return false;
}

// The total length of the visible and kept parts of [0, D], where the last
// ends and how many there are.
avos_real avos_visibleLength(avos_real D, out avos_real lastEnd, out int parts)
{
  avos_real L = avos_real(0.0);
  lastEnd = avos_real(0.0);
  parts = 0;
  avos_real begin;
  avos_real end;
  int kept;
  avos_Walk walk = avos_startWalk(D);
  while (avos_nextPart(walk, D, begin, end, kept))
  {
    L += end - begin;
    lastEnd = end;
    ++parts;
  }
  return L;
}

// The core's IntegrateRiemann (exponential form) over the visible parts,
// each kept part its own ray from its entry (vtkAdaptiveVolumeMapper's
// ClippedRiemann: as VTK's mappers start a clipped ray): samples at
// entry + min(i h, its length) that lie inside the visible parts.
vec4 avos_riemann(avos_real D, float h, float bound)
{
  vec3 colour = vec3(0.0);
  float T = 1.0;
  avos_Walk walk = avos_startWalk(D);
  int kept = -1;                  // the kept part being sampled
  avos_real base = avos_real(0.0); // its entry
  avos_real length = avos_real(0.0);
  int n = 0;
  int next = 1; // the first sample index not yet taken
  bool inside = false; // a part has been taken
  avos_real begin;
  avos_real end;
  // One loop (see avos_adaptive): each pass takes a sample or the next part.
  for (;;)
  {
    avos_real t1 = next >= n ? base + length : base + min(avos_real(next) * avos_real(h), length);
    if (!inside || next > n || t1 > end)
    {
      int part;
      if (!avos_nextPart(walk, D, begin, end, part))
      {
        break;
      }
      inside = true;
      if (part != kept)
      {
        kept = part;
        base = avos_kept[part].x;
        length = avos_kept[part].y - base;
        n = int(ceil(length / avos_real(h)));
        next = 1;
      }
      next = max(max(next, int(ceil((begin - base) / avos_real(h)))), 1);
      continue;
    }
    float dt = float(t1 - base - avos_real(next - 1) * avos_real(h));
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

// Simpson's estimate assumes a smooth integrand: the factor for a
// bracket's scalars v read through function f (SimpsonErrorScale), 15
// across a jump of f, 5 across a kink, 1 otherwise, over their range
// widened by the largest step between neighbours.
float avos_rangeScale(float v[5], int f)
{
  float lo = v[0];
  float hi = lo;
  float spread = 0.0;
  for (int i = 1; i < 5; ++i)
  {
    lo = min(lo, v[i]);
    hi = max(hi, v[i]);
    spread = max(spread, abs(v[i] - v[i - 1]));
  }
  lo = max(lo - spread, avos_fieldRange.x);
  hi = min(hi + spread, avos_fieldRange.y);
  if (!(lo == lo && hi == hi && lo < hi))
  {
    return 1.0;
  }
  return avos_hasJumpInOf(f, lo, hi) ? 15.0 : (avos_hasKnotInOf(f, lo, hi) ? 5.0 : 1.0);
}

#ifdef AVOS_MIXTURE
// The factor for component k of a mixture through function f.
float avos_componentScale(avos_Bracket b, int k, int f)
{
  return avos_rangeScale(float[5](b.S[0].Scalars[k], b.S[1].Scalars[k], b.S[2].Scalars[k],
                           b.S[3].Scalars[k], b.S[4].Scalars[k]),
    f);
}

// Component k read through function f (independent ones of weight 0 are
// not read).
#define AVOS_MIX_SCALE(k, f)                                                                       \
  if (AVOS_MIX_KIND != 1 || avos_mixWeight[k] > 0.0)                                               \
  {                                                                                                \
    b.Scale = max(b.Scale, avos_componentScale(b, k, f));                                          \
  }
#endif

// The bracket's factor (Bracket::EstimateScale), computed once: its
// scalars' avos_rangeScale; a mixture's, the largest over the components it
// reads through a function.
float avos_estimateScale(inout avos_Bracket b)
{
  if (b.Scale > 0.0)
  {
    return b.Scale;
  }
#ifdef AVOS_MIXTURE
  b.Scale = 1.0;
#if AVOS_MIX_KIND == 1
  AVOS_MIX_SCALE(0, 0)
  AVOS_MIX_SCALE(1, 1)
#if AVOS_MIXTURE > 2
  AVOS_MIX_SCALE(2, 2)
#endif
#if AVOS_MIXTURE > 3
  AVOS_MIX_SCALE(3, 3)
#endif
#elif AVOS_MIX_KIND == 2
  AVOS_MIX_SCALE(0, 0)
  AVOS_MIX_SCALE(1, 0)
#else
  AVOS_MIX_SCALE(3, 0)
#endif
  return b.Scale;
#endif
  b.Scale = avos_rangeScale(
    float[5](b.S[0].Scalar, b.S[1].Scalar, b.S[2].Scalar, b.S[3].Scalar, b.S[4].Scalar), 0);
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
  avos_real lastEnd;
  int parts;
  avos_real L = avos_visibleLength(D, lastEnd, parts);
  avos_real begin;
  avos_real end;
  int kept; // unused: every visible and kept part alike
  avos_Walk walk;
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
      if (part == parts || !avos_nextPart(walk, D, first, last, kept))
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
  w.Cells = avos_walkCells();
  avos_real3 p = avos_walkOrigin + tBegin * avos_walkDirection;
  for (int a = 0; a < 3; ++a)
  {
    avos_real x = clamp(p[a], avos_real(0.0), avos_real(w.Cells[a]));
    w.Index[a] = min(int(x), w.Cells[a] - 1);
    avos_real d = avos_walkDirection[a];
    w.Stride[a] = d > avos_real(0.0) ? 1 : (d < avos_real(0.0) ? -1 : 0);
    w.TMax[a] = w.Stride[a] > 0 ? (avos_real(w.Index[a] + 1) - avos_walkOrigin[a]) / d
      : (w.Stride[a] < 0 ? (avos_real(w.Index[a]) - avos_walkOrigin[a]) / d : avos_real(3.0e38));
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

// A walk cell's corners (x fastest), false when one is not finite (the cell
// is undefined: passed over by every method but the samplers).
bool avos_corners(ivec3 cell, out float c[8])
{
  avos_cornerValues(cell, c);
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
  avos_real3 e = avos_walkOrigin + t0 * avos_walkDirection - avos_real3(cell);
  avos_real3 d = avos_walkDirection;
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
// corner too. Every cell of the kept parts is walked: the blocks'
// visibility is the composite integral's, not the projections'. `side` 1
// for the maximum, -1 for the minimum; false when no finite cell lies on
// the ray.
bool avos_extremum(avos_real D, float side, out avos_real value)
{
  avos_real best = avos_real(-3.0e38);
  bool found = false;
  int kept = 0;
  avos_CellWalk walk = avos_startCells(avos_kept[0].x, avos_kept[0].y);
  ivec3 cell;
  avos_real t0;
  avos_real t1;
  for (;;)
  {
    if (!avos_nextCell(walk, cell, t0, t1))
    {
      if (++kept >= avos_keptCount)
      {
        break;
      }
      walk = avos_startCells(avos_kept[kept].x, avos_kept[kept].y);
      continue;
    }
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

// ------------------------------------------------ the piecewise method
// numerics::IntegratePiecewise (PiecewiseIntegrator.h) where the context has
// fp64 (the mapper refuses it elsewhere): the ray cut into pieces at cell
// faces, at the extrema of each cell's cubic (every piece is monotone) and
// where the cubic crosses a knot of numerics::PiecewiseTransferFunction
// (avos_pp*, per piece: (Start, tau, tau', tau''), (tau''', the visible
// pieces among the first i + 1, max |colour slope|, 0), the colour and its
// slope; tau a cubic in d = s - Start, the colour linear). On a piece, v in
// [0, l] from its start and d(v) a cubic, the optical depth theta(v) is the
// integral of a polynomial (degree at most 10), exact; the colour integral
// is, by parts,
//   C(0) T(0) - C(l) T(l) + c1 T(0) J,  J = int_0^l d'(v) e^{-theta(v)} dv.
// d is monotone and e^{-theta} decreases, so J lies between dq e^{-theta(l)}
// and dq (second mean value theorem): where the midpoint of those bounds,
// times max |c1| T(0), fits the core's share 0.6 eps (T(0) (1 - E_l) +
// l / L) / 2 (L the ray's visible length: the shares add up to 0.6 eps) it
// is J; elsewhere J is the sum of the power series of e^{-theta} on
// sub-intervals, each truncated where a dominating series proves the rest
// within the sub-interval's share (avos_seriesJ, the CPU's SeriesIntegrals
// with at most 16 terms instead of 40: a sub-interval that needs more is
// halved). 0.15 eps goes to early termination and, in VTK's alpha model,
// 0.25 eps to the extinction's relative error eps / 8 (the pieces'
// construction), as on the CPU. llvmpipe counts every iteration of every
// loop it keeps against one limit per group of fragments (avos_castRay), so
// the loops of fixed length (the series' terms, the polynomials'
// coefficients, the knot search) are written out: only the walk, the
// pieces, the knot crossings and the sub-intervals count (at most a few
// hundred per ray on the tests' scenes).

// e^x for x <= 0 in double (GLSL's exp has no double overload):
// x = k ln 2 + r, |r| <= ln 2 / 2 (ln 2 in two parts, the first exact in
// k ln 2 for |k| < 2^11), e^r by its Taylor polynomial of degree 13
// (remainder below 2e-17), times 2^k.
avos_real avos_exp(avos_real x)
{
  if (x < avos_real(-708.0))
  {
    return avos_real(0.0);
  }
  avos_real k = floor(x * avos_real(1.4426950408889634) + avos_real(0.5));
  avos_real r = (x - k * avos_real(0.693145751953125)) - k * avos_real(1.4286068203094173e-06);
  // Written out: llvmpipe counts every iteration of a loop it keeps.
  avos_real e = avos_real(1.0) + r / avos_real(13.0);
  e = avos_real(1.0) + e * r / avos_real(12.0);
  e = avos_real(1.0) + e * r / avos_real(11.0);
  e = avos_real(1.0) + e * r / avos_real(10.0);
  e = avos_real(1.0) + e * r / avos_real(9.0);
  e = avos_real(1.0) + e * r / avos_real(8.0);
  e = avos_real(1.0) + e * r / avos_real(7.0);
  e = avos_real(1.0) + e * r / avos_real(6.0);
  e = avos_real(1.0) + e * r / avos_real(5.0);
  e = avos_real(1.0) + e * r / avos_real(4.0);
  e = avos_real(1.0) + e * r / avos_real(3.0);
  e = avos_real(1.0) + e * r / avos_real(2.0);
  e = avos_real(1.0) + e * r;
  return avos_ldexp(e, int(k));
}

// The piece holding s: pieces i >= 1 start at the knots (right-continuous
// at a jump), piece 0 holds what lies below (PiecewiseTransferFunction's
// Locate). A binary search of a fixed 12 steps (up to 4096 pieces, which
// the uniforms never hold), written out as the other fixed loops of this
// method: llvmpipe counts every iteration of a loop it keeps against its
// limit (see avos_castRay).
#define AVOS_LOCATE_STEP(k)                                                                        \
  next = lo + k;                                                                                   \
  lo = next < avos_ppCount && avos_real(avos_ppA[min(next, avos_ppCount - 1)].x) <= s ? next : lo;
int avos_ppLocate(avos_real s)
{
  int lo = 0;
  int next;
  AVOS_LOCATE_STEP(2048)
  AVOS_LOCATE_STEP(1024)
  AVOS_LOCATE_STEP(512)
  AVOS_LOCATE_STEP(256)
  AVOS_LOCATE_STEP(128)
  AVOS_LOCATE_STEP(64)
  AVOS_LOCATE_STEP(32)
  AVOS_LOCATE_STEP(16)
  AVOS_LOCATE_STEP(8)
  AVOS_LOCATE_STEP(4)
  AVOS_LOCATE_STEP(2)
  AVOS_LOCATE_STEP(1)
  return lo;
}

float avos_ppVisibleBefore(int i)
{
  return i > 0 ? avos_ppB[i - 1].y : 0.0;
}

// The root of q(u) = value in [a, b], where q - value changes sign (q
// monotone there): Newton's steps kept inside the bracket, bisection where
// one would leave it, until the bracket or the step vanishes; at most 64
// steps. The first 8 are written out (a crossing rarely needs more; llvmpipe
// counts a loop's iterations against its limit, and a ray through noisy
// data crosses knots thousands of times).
#define AVOS_NEWTON_STEP                                                                           \
  if (!done)                                                                                       \
  {                                                                                                \
    avos_real f = avos_at(q, u) - value;                                                           \
    if (f == avos_real(0.0))                                                                       \
    {                                                                                              \
      done = true;                                                                                 \
    }                                                                                              \
    else                                                                                           \
    {                                                                                              \
      if ((f < avos_real(0.0)) == (fa < avos_real(0.0)))                                           \
      {                                                                                            \
        a = u;                                                                                     \
        fa = f;                                                                                    \
      }                                                                                            \
      else                                                                                         \
      {                                                                                            \
        b = u;                                                                                     \
      }                                                                                            \
      avos_real slope = q.K[1] + u * (avos_real(2.0) * q.K[2] + u * avos_real(3.0) * q.K[3]);      \
      avos_real next = slope != avos_real(0.0) ? u - f / slope : a;                                \
      next = next > a && next < b ? next : avos_real(0.5) * (a + b);                               \
      done = next == u || b - a <= avos_real(1e-15) * max(abs(a), abs(b));                         \
      u = next;                                                                                    \
    }                                                                                              \
  }
avos_real avos_crossing(avos_Cubic q, avos_real value, avos_real a, avos_real b)
{
  avos_real fa = avos_at(q, a) - value;
  avos_real u = avos_real(0.5) * (a + b);
  bool done = false;
  AVOS_NEWTON_STEP AVOS_NEWTON_STEP AVOS_NEWTON_STEP AVOS_NEWTON_STEP
  AVOS_NEWTON_STEP AVOS_NEWTON_STEP AVOS_NEWTON_STEP AVOS_NEWTON_STEP
  for (int i = 8; i < 64 && !done; ++i)
  {
    AVOS_NEWTON_STEP
  }
  return u;
}

// A ray of the piecewise method.
struct avos_PiecewiseRay
{
  avos_real3 Colour;
  avos_real T;
  avos_real InverseL; // 1 / the ray's visible length
  avos_real Budget;   // 0.6 eps
  bool Failed;        // a piece beyond its sub-interval bound
};

// The depth polynomial theta[0..10] at v (theta[0] = 0 before a shift).
avos_real avos_depth(avos_real theta[11], avos_real v)
{
  avos_real p = theta[10];
  p = p * v + theta[9];
  p = p * v + theta[8];
  p = p * v + theta[7];
  p = p * v + theta[6];
  p = p * v + theta[5];
  p = p * v + theta[4];
  p = p * v + theta[3];
  p = p * v + theta[2];
  p = p * v + theta[1];
  return max(p * v + theta[0], avos_real(0.0));
}

// p(v0 + w) in powers of w (numerics::detail::ShiftPolynomial) for the
// depth (degree 10: the coefficients above its degree are 0) and for q'
// (degree 2).
void avos_shiftDepth(inout avos_real c[11], avos_real v0)
{
  // Row i: c[j] += v0 c[j + 1] for j = 9 down to i, i = 0 .. 9, written out.
  c[9] += v0 * c[10]; c[8] += v0 * c[9]; c[7] += v0 * c[8]; c[6] += v0 * c[7]; c[5] += v0 * c[6];
  c[4] += v0 * c[5]; c[3] += v0 * c[4]; c[2] += v0 * c[3]; c[1] += v0 * c[2]; c[0] += v0 * c[1];
  c[9] += v0 * c[10]; c[8] += v0 * c[9]; c[7] += v0 * c[8]; c[6] += v0 * c[7]; c[5] += v0 * c[6];
  c[4] += v0 * c[5]; c[3] += v0 * c[4]; c[2] += v0 * c[3]; c[1] += v0 * c[2];
  c[9] += v0 * c[10]; c[8] += v0 * c[9]; c[7] += v0 * c[8]; c[6] += v0 * c[7]; c[5] += v0 * c[6];
  c[4] += v0 * c[5]; c[3] += v0 * c[4]; c[2] += v0 * c[3];
  c[9] += v0 * c[10]; c[8] += v0 * c[9]; c[7] += v0 * c[8]; c[6] += v0 * c[7]; c[5] += v0 * c[6];
  c[4] += v0 * c[5]; c[3] += v0 * c[4];
  c[9] += v0 * c[10]; c[8] += v0 * c[9]; c[7] += v0 * c[8]; c[6] += v0 * c[7]; c[5] += v0 * c[6];
  c[4] += v0 * c[5];
  c[9] += v0 * c[10]; c[8] += v0 * c[9]; c[7] += v0 * c[8]; c[6] += v0 * c[7]; c[5] += v0 * c[6];
  c[9] += v0 * c[10]; c[8] += v0 * c[9]; c[7] += v0 * c[8]; c[6] += v0 * c[7];
  c[9] += v0 * c[10]; c[8] += v0 * c[9]; c[7] += v0 * c[8];
  c[9] += v0 * c[10]; c[8] += v0 * c[9];
  c[9] += v0 * c[10];
}

void avos_shiftSlope(inout avos_real g[3], avos_real v0)
{
  g[0] += v0 * (g[1] + v0 * g[2]);
  g[1] += avos_real(2.0) * v0 * g[2];
}

// sum_j |theta_j| h^j (j >= 1): the dominating series' exponent at h.
avos_real avos_magnitude(avos_real theta[11], avos_real h)
{
  avos_real a = abs(theta[10]) * h;
  a = (a + abs(theta[9])) * h;
  a = (a + abs(theta[8])) * h;
  a = (a + abs(theta[7])) * h;
  a = (a + abs(theta[6])) * h;
  a = (a + abs(theta[5])) * h;
  a = (a + abs(theta[4])) * h;
  a = (a + abs(theta[3])) * h;
  a = (a + abs(theta[2])) * h;
  return (a + abs(theta[1])) * h;
}

// The series' most terms on a sub-interval (the CPU takes up to 40).
const int avos_terms = 16;

// Term k of avos_series: int_0^h g(w) c_k w^k dw added until settled.
#define AVOS_TERM(k)                                                                               \
  if (!settled)                                                                                    \
  {                                                                                                \
    moment = g[2] / avos_real(k + 3);                                                              \
    moment = g[1] / avos_real(k + 2) + h * moment;                                                 \
    moment = g[0] / avos_real(k + 1) + h * moment;                                                 \
    sum += c[k] * hk * h * moment;                                                                 \
    settled = Ev * h * gmax * max(whole - partial, avos_real(0.0)) <= limit;                       \
  }
// c_k+1 and C_k+1 from the recursion's terms j = 1 .. min(10, k + 1).
#define AVOS_RECUR(k, j)                                                                           \
  if (j <= k + 1)                                                                                  \
  {                                                                                                \
    next -= avos_real(j) * theta[j] * c[max(k + 1 - j, 0)];                                        \
    majorant += abs(avos_real(j) * theta[j]) * C[max(k + 1 - j, 0)];                               \
  }
#define AVOS_NEXT(k)                                                                               \
  next = avos_real(0.0);                                                                           \
  majorant = avos_real(0.0);                                                                       \
  AVOS_RECUR(k, 1) AVOS_RECUR(k, 2) AVOS_RECUR(k, 3) AVOS_RECUR(k, 4) AVOS_RECUR(k, 5)             \
  AVOS_RECUR(k, 6) AVOS_RECUR(k, 7) AVOS_RECUR(k, 8) AVOS_RECUR(k, 9) AVOS_RECUR(k, 10)            \
  c[k + 1] = next / avos_real(k + 1);                                                              \
  C[k + 1] = majorant / avos_real(k + 1);                                                          \
  hk *= h;                                                                                         \
  partial += C[k + 1] * hk;

// numerics::detail::SubintervalSeries for J alone: the integral of
// g(w) e^{-theta(w)} over [0, h] (theta shifted to the sub-interval, A =
// avos_magnitude(theta, h) <= 1), e^{-theta} as its power series c_k
// ((k + 1) c_k+1 = -sum_j j theta_j c_k+1-j), dominated term by term by
// that of e^{A(w)} (C_k, the same recursion on |theta_j|), whose sum at h is
// e^A: truncated after k terms the integral errs by at most
// Ev h max|g| (e^A - sum_{i <= k} C_i h^i). Terms are added until that is
// within `limit`; false when 16 do not suffice. Written out (see
// avos_ppLocate).
bool avos_series(avos_real theta[11], avos_real g[3], avos_real h, avos_real A, avos_real Ev,
  avos_real limit, out avos_real sum)
{
  avos_real gmax = abs(g[0]) + h * (abs(g[1]) + h * abs(g[2]));
  avos_real whole = avos_exp(A);
  avos_real c[avos_terms + 1];
  avos_real C[avos_terms + 1];
  c[0] = avos_real(1.0);
  C[0] = avos_real(1.0);
  avos_real partial = avos_real(1.0);
  avos_real hk = avos_real(1.0);
  sum = avos_real(0.0);
  bool settled = false;
  avos_real next;
  avos_real majorant;
  avos_real moment;
  // Term k, then the next coefficients (written out: see avos_ppLocate).
  AVOS_TERM(0) AVOS_NEXT(0) AVOS_TERM(1) AVOS_NEXT(1) AVOS_TERM(2) AVOS_NEXT(2)
  AVOS_TERM(3) AVOS_NEXT(3) AVOS_TERM(4) AVOS_NEXT(4) AVOS_TERM(5) AVOS_NEXT(5)
  AVOS_TERM(6) AVOS_NEXT(6) AVOS_TERM(7) AVOS_NEXT(7) AVOS_TERM(8) AVOS_NEXT(8)
  AVOS_TERM(9) AVOS_NEXT(9) AVOS_TERM(10) AVOS_NEXT(10) AVOS_TERM(11) AVOS_NEXT(11)
  AVOS_TERM(12) AVOS_NEXT(12) AVOS_TERM(13) AVOS_NEXT(13) AVOS_TERM(14) AVOS_NEXT(14)
  AVOS_TERM(15) AVOS_NEXT(15) AVOS_TERM(16)
  return settled;
}

// J = int_0^l d'(v) e^{-theta(v)} dv on a monotone piece whose midpoint
// bound did not fit (numerics::detail::SeriesIntegrals): sub-intervals
// [v, v + h] allowed scale (front (E_v - E_v+h) + h / L), where the shifted
// depth has A <= 1 and the series meets that share; halved otherwise, then
// doubled again. The rest of J is dropped once E_v times the variation of d
// over the rest fits the rest's share. Where A stays above 1 or the series
// does not settle at 2^-40 of the piece, the midpoint of the sub-interval's
// bounds (proven within half their difference). Returns false beyond 2^16
// sub-intervals (extreme data only, as on the CPU).
bool avos_seriesJ(avos_real theta[11], avos_real d[4], avos_real l, avos_real El,
  avos_real scale, avos_real front, avos_real inverseL, out avos_real J)
{
  J = avos_real(0.0);
  avos_real v = avos_real(0.0);
  avos_real h = l;
  avos_real Ev = avos_real(1.0);
  avos_real floor = l * avos_real(9.094947017729282e-13); // 2^-40
  for (int count = 0; v < l; ++count)
  {
    if (count == 65536)
    {
      return false;
    }
    h = min(h, l - v);
    avos_real ts[11] = theta;
    avos_shiftDepth(ts, v);
    avos_real gs[3] = avos_real[3](d[1], avos_real(2.0) * d[2], avos_real(3.0) * d[3]);
    avos_shiftSlope(gs, v);
    avos_real rest = l - v;
    avos_real variation = rest * (abs(gs[0]) + rest * (abs(gs[1]) + rest * abs(gs[2])));
    if (Ev * variation <= scale * (front * (Ev - El) + rest * inverseL))
    {
      return true;
    }
    avos_real A = avos_magnitude(ts, h);
    while (A > avos_real(1.0) && h > floor)
    {
      h = max(avos_real(0.5) * h, floor);
      A = avos_magnitude(ts, h);
    }
    avos_real end = l - v <= h ? l : v + h;
    avos_real Eh = end == l ? El : avos_exp(-avos_depth(theta, end));
    avos_real sum;
    bool settled = A <= avos_real(1.0) &&
      avos_series(ts, gs, h, A, Ev, scale * (front * (Ev - Eh) + h * inverseL), sum);
    if (settled)
    {
      J += Ev * sum;
    }
    else if (h > floor && A <= avos_real(1.0))
    {
      h = max(avos_real(0.5) * h, floor);
      continue;
    }
    else
    {
      // The midpoint of int g between Eh and Ev (g keeps its sign).
      J += h * (gs[0] + h * (gs[1] / avos_real(2.0) + h * gs[2] / avos_real(3.0))) *
        (Ev + Eh) * avos_real(0.5);
    }
    v = end;
    Ev = Eh;
    h *= avos_real(2.0);
  }
  return true;
}

// Piece `i` of the transfer function over [ua, ub] of the cell's cubic q.
void avos_integratePiece(inout avos_PiecewiseRay ray, avos_Cubic q, int i, avos_real ua,
  avos_real ub)
{
  if (!(avos_ppB[i].y > avos_ppVisibleBefore(i)))
  {
    return; // tau = 0 on the whole piece
  }
  avos_real start = avos_real(avos_ppA[i].x);
  avos_real l = ub - ua;
  // d(v) = s(ua + v) - Start.
  avos_real d[4];
  d[0] = avos_at(q, ua) - start;
  d[1] = q.K[1] + ua * (avos_real(2.0) * q.K[2] + ua * avos_real(3.0) * q.K[3]);
  d[2] = q.K[2] + avos_real(3.0) * q.K[3] * ua;
  d[3] = q.K[3];
  // tau(v) = t0 + t1 d + t2 d^2 + t3 d^3 (degree 9 in v); theta[j] the
  // coefficient of v^j of its integral.
  avos_real t2 = avos_real(avos_ppA[i].w);
  avos_real t3 = avos_real(avos_ppB[i].x);
  avos_real square[7];
  square[0] = d[0] * d[0];
  square[1] = avos_real(2.0) * d[0] * d[1];
  square[2] = avos_real(2.0) * d[0] * d[2] + d[1] * d[1];
  square[3] = avos_real(2.0) * (d[0] * d[3] + d[1] * d[2]);
  square[4] = avos_real(2.0) * d[1] * d[3] + d[2] * d[2];
  square[5] = avos_real(2.0) * d[2] * d[3];
  square[6] = d[3] * d[3];
  avos_real cube[10];
  cube[0] = square[0] * d[0];
  cube[1] = square[0] * d[1] + square[1] * d[0];
  cube[2] = square[0] * d[2] + square[1] * d[1] + square[2] * d[0];
  cube[3] = square[0] * d[3] + square[1] * d[2] + square[2] * d[1] + square[3] * d[0];
  cube[4] = square[1] * d[3] + square[2] * d[2] + square[3] * d[1] + square[4] * d[0];
  cube[5] = square[2] * d[3] + square[3] * d[2] + square[4] * d[1] + square[5] * d[0];
  cube[6] = square[3] * d[3] + square[4] * d[2] + square[5] * d[1] + square[6] * d[0];
  cube[7] = square[4] * d[3] + square[5] * d[2] + square[6] * d[1];
  cube[8] = square[5] * d[3] + square[6] * d[2];
  cube[9] = square[6] * d[3];
  avos_real t0 = avos_real(avos_ppA[i].y);
  avos_real t1 = avos_real(avos_ppA[i].z);
  avos_real theta[11];
  theta[0] = avos_real(0.0);
  theta[1] = t0 + t1 * d[0] + t2 * square[0] + t3 * cube[0];
  theta[2] = (t1 * d[1] + t2 * square[1] + t3 * cube[1]) / avos_real(2.0);
  theta[3] = (t1 * d[2] + t2 * square[2] + t3 * cube[2]) / avos_real(3.0);
  theta[4] = (t1 * d[3] + t2 * square[3] + t3 * cube[3]) / avos_real(4.0);
  theta[5] = (t2 * square[4] + t3 * cube[4]) / avos_real(5.0);
  theta[6] = (t2 * square[5] + t3 * cube[5]) / avos_real(6.0);
  theta[7] = (t2 * square[6] + t3 * cube[6]) / avos_real(7.0);
  theta[8] = t3 * cube[7] / avos_real(8.0);
  theta[9] = t3 * cube[8] / avos_real(9.0);
  theta[10] = t3 * cube[9] / avos_real(10.0);

  avos_real Ta = ray.T;
  avos_real EL = avos_exp(-avos_depth(theta, l));
  avos_real3 c0 = avos_real3(avos_ppC[i].rgb);
  avos_real3 c1 = avos_real3(avos_ppS[i].rgb);
  avos_real qa = d[0];
  avos_real ql = avos_at(q, ub) - start;
  ray.Colour += Ta * (c0 + c1 * qa) - Ta * EL * (c0 + c1 * ql);
  ray.T = Ta * EL;
  avos_real cs = avos_real(avos_ppB[i].z);
  if (!(cs > avos_real(0.0) && Ta > avos_real(0.0)))
  {
    return;
  }
  avos_real dq = ql - qa;
  avos_real J = dq * (avos_real(1.0) + EL) * avos_real(0.5);
  if (cs * Ta * abs(dq) * (avos_real(1.0) - EL) >
      ray.Budget * (Ta * (avos_real(1.0) - EL) + l * ray.InverseL) &&
    !avos_seriesJ(theta, d, l, EL, ray.Budget / (avos_real(2.0) * cs * Ta), Ta, ray.InverseL, J))
  {
    ray.Failed = true;
    return;
  }
  ray.Colour += c1 * (Ta * J);
}

// ------------------------------------ the additive and average projections
// numerics::AdditiveAlongRay and AverageAlongRay (Accumulation.h) on the
// piece walk, n = (s - smin) / (smax - smin) over the data's range
// (avos_accumulationRange: smin and 1 / (smax - smin)). Additive: per piece
// of the transfer function, int tau n by 7-point Gauss-Legendre, exact
// (tau n is a polynomial of degree at most 12 in the ray's parameter). The
// ray's sum goes into Colour.x.
#define AVOS_NODE(x, w)                                                                            \
  d = avos_at(q, mid + radius * (x)) - start;                                                      \
  sum += (w) * (t0 + d * (t1 + d * (t2 + d * t3))) * (start + d - smin);
#define AVOS_NODES(x, w)                                                                           \
  AVOS_NODE(-AVOS_DOUBLE(x), AVOS_DOUBLE(w)) AVOS_NODE(AVOS_DOUBLE(x), AVOS_DOUBLE(w))
void avos_addPiece(inout avos_PiecewiseRay ray, avos_Cubic q, int i, avos_real ua, avos_real ub)
{
  if (!(avos_ppB[i].y > avos_ppVisibleBefore(i)))
  {
    return; // tau = 0 on the whole piece
  }
  avos_real start = avos_real(avos_ppA[i].x);
  avos_real t0 = avos_real(avos_ppA[i].y);
  avos_real t1 = avos_real(avos_ppA[i].z);
  avos_real t2 = avos_real(avos_ppA[i].w);
  avos_real t3 = avos_real(avos_ppB[i].x);
  avos_real smin = avos_real(avos_accumulationRange.x);
  avos_real radius = avos_real(0.5) * (ub - ua);
  avos_real mid = avos_real(0.5) * (ua + ub);
  avos_real sum = avos_real(0.0);
  avos_real d;
  AVOS_NODES(0.9491079123427585, 0.1294849661688697)
  AVOS_NODES(0.7415311855993945, 0.2797053914892766)
  AVOS_NODES(0.4058451513773972, 0.3818300505051189)
  AVOS_NODE(avos_real(0.0), AVOS_DOUBLE(0.4179591836734694))
  ray.Colour.x += radius * sum * avos_real(avos_accumulationRange.y);
}

// The average's integrand alpha_h(s) n(s) at u, alpha_h = 1 - exp(-tau h)
// the opacity of a slab of the sample distance h (avos_steps.w), tau from
// the transfer function's piece k (avos_lookUp's, found once per piece of
// the range: those are cut at every knot).
avos_real avos_averaged(avos_Cubic q, int k, avos_real u)
{
  float s = float(avos_at(q, u));
  float opacity;
  vec3 colour; // unused
  avos_pieceAt(k, s, opacity, colour);
  return avos_real(avos_oneMinusExp(avos_toExtinction(opacity) * avos_steps.w) *
    (s - avos_accumulationRange.x) * avos_accumulationRange.y);
}

// int_a^b of the average's integrand by Gauss-Legendre of 4 (coarse) and 8
// (fine) nodes, symmetric pairs of nodes at a time.
#define AVOS_GAUSS(sum, x, w)                                                                      \
  sum += AVOS_DOUBLE(w) *                                                                          \
    (avos_averaged(q, k, mid - radius * AVOS_DOUBLE(x)) +                                          \
      avos_averaged(q, k, mid + radius * AVOS_DOUBLE(x)));
void avos_gauss(avos_Cubic q, int k, avos_real a, avos_real b, out avos_real coarse,
  out avos_real fine)
{
  avos_real radius = avos_real(0.5) * (b - a);
  avos_real mid = avos_real(0.5) * (a + b);
  coarse = avos_real(0.0);
  fine = avos_real(0.0);
  AVOS_GAUSS(coarse, 0.8611363115940526, 0.3478548451374538)
  AVOS_GAUSS(coarse, 0.3399810435848563, 0.6521451548625461)
  AVOS_GAUSS(fine, 0.9602898564975363, 0.1012285362903763)
  AVOS_GAUSS(fine, 0.7966664774136267, 0.2223810344533745)
  AVOS_GAUSS(fine, 0.5255324099163290, 0.3137066458778873)
  AVOS_GAUSS(fine, 0.1834346424956498, 0.3626837833783620)
  coarse *= radius;
  fine *= radius;
}

// Average: a piece of the range's marks (avos_pp holds the pieces of
// numerics::AverageRange: visible inside [r0, r1], cut at the transfer
// function's knots; avos_ppB.z 1 where the transfer function is transparent)
// adds its length to Colour.y and, unless transparent, int alpha_h n to
// Colour.x: Gauss-Legendre 8 against 4, the piece halved while they differ
// by more than the tolerance times the part's length (AdaptiveGauss's rule,
// so the mean is within the tolerance), walked depth first without a stack
// (a part is the dyadic interval `index` of its `level`). At level 20 the
// 8-node value is taken, as on the CPU; a piece that needs more than 4096
// parts fails the ray (reported, never shown).
void avos_averagePiece(
  inout avos_PiecewiseRay ray, avos_Cubic q, int i, avos_real ua, avos_real ub)
{
  if (!(avos_ppB[i].y > avos_ppVisibleBefore(i)))
  {
    return; // outside the range
  }
  avos_real length = ub - ua;
  ray.Colour.y += length;
  if (avos_ppB[i].z != 0.0)
  {
    return;
  }
  int k = avos_locate(float(avos_at(q, avos_real(0.5) * (ua + ub))));
  int level = 0;
  int index = 0;
  for (int n = 0; n < 4096; ++n)
  {
    avos_real width = avos_ldexp(length, -level);
    avos_real a = ua + avos_real(index) * width;
    avos_real coarse;
    avos_real fine;
    avos_gauss(q, k, a, a + width, coarse, fine);
    if (abs(fine - coarse) <= avos_real(avos_tolerance) * width ||
      level >= 20)
    {
      ray.Colour.x += fine;
      // Up past the parts whose right half this was, then to the next one.
      for (int up = 0; up < 21 && (index & 1) == 1; ++up)
      {
        index >>= 1;
        --level;
      }
      if (level == 0)
      {
        return;
      }
      ++index;
    }
    else
    {
      ++level;
      index *= 2;
    }
  }
  ray.Failed = true;
}

// Where the piecewise walk stands on a ray: the cell (its cubic Q from the
// entry of its part, the corners' range, the ends of its monotone stretches
// Ends[0..Stretches]), the stretch (its pieces First..Last of the transfer
// function, in the order of u: rising or falling) and the next piece (Next
// of them, from U).
struct avos_PieceWalk
{
  avos_Cubic Q;
  float Lo;
  float Hi;
  avos_real Ends[4];
  int Stretches;
  int Stretch;
  bool Rising;
  int First;
  int Last;
  int Next;
  avos_real U;
};

// Starts the walk's next stretch (Stretch + 1): its end values and pieces.
void avos_startStretch(inout avos_PieceWalk w)
{
  ++w.Stretch;
  avos_real ua = w.Ends[w.Stretch];
  avos_real ub = w.Ends[w.Stretch + 1];
  avos_real sa = clamp(avos_at(w.Q, ua), avos_real(w.Lo), avos_real(w.Hi));
  avos_real sb = clamp(avos_at(w.Q, ub), avos_real(w.Lo), avos_real(w.Hi));
  w.Rising = sb >= sa;
  w.First = avos_ppLocate(min(sa, sb));
  w.Last = avos_ppLocate(max(sa, sb));
  w.Next = 0;
  w.U = ua;
}

// Starts the walk on a cell's part [t0, t1] of the ray: false when the
// transfer function makes its corners' range transparent (or a corner is
// not finite: the cell is undefined, empty).
bool avos_startCell(inout avos_PieceWalk w, ivec3 cell, avos_real t0, avos_real t1)
{
  float c[8];
  if (!avos_corners(cell, c))
  {
    return false;
  }
  w.Lo = min(min(min(c[0], c[1]), min(c[2], c[3])), min(min(c[4], c[5]), min(c[6], c[7])));
  w.Hi = max(max(max(c[0], c[1]), max(c[2], c[3])), max(max(c[4], c[5]), max(c[6], c[7])));
  if (!(avos_ppB[avos_ppLocate(avos_real(w.Hi))].y >
        avos_ppVisibleBefore(avos_ppLocate(avos_real(w.Lo)))))
  {
    return false;
  }
  ++avos_samples;
  w.Q = avos_cellCubic(c, cell, t0);
  avos_real extent = t1 - t0;
  avos_real roots[2];
  w.Stretches = avos_extrema(w.Q, extent, roots) + 1;
  w.Ends = avos_real[4](avos_real(0.0), roots[0], roots[1], extent);
  w.Ends[w.Stretches] = extent;
  w.Stretch = -1;
  avos_startStretch(w);
  return true;
}

// Integrates the stretch's next piece: from U to where q crosses the next
// knot (after the piece's start rising, its own start falling), or to the
// stretch's end.
void avos_nextPiece(inout avos_PieceWalk w, inout avos_PiecewiseRay ray)
{
  int p = w.Rising ? w.First + w.Next : w.Last - w.Next;
  avos_real ub = w.Ends[w.Stretch + 1];
  avos_real end = ub;
  if (w.Next < w.Last - w.First)
  {
    avos_real knot = avos_real(avos_ppA[w.Rising ? p + 1 : p].x);
    end = clamp(avos_crossing(w.Q, knot, w.Ends[w.Stretch], ub), w.U, ub);
  }
  if (end > w.U)
  {
    if (avos_blend == 3)
    {
      avos_addPiece(ray, w.Q, p, w.U, end);
    }
    else if (avos_blend == 4)
    {
      avos_averagePiece(ray, w.Q, p, w.U, end);
    }
    else
    {
      avos_integratePiece(ray, w.Q, p, w.U, end);
    }
  }
  w.U = end;
  ++w.Next;
}

// The pieces of the visible parts of [0, D] through the blend's per-piece
// integral (avos_nextPiece), until the ray's transmittance reaches `bound`
// or it fails. One loop: each pass integrates a piece or moves to the next
// stretch, cell or part, so the fragments of a SIMD group (llvmpipe, GPU
// warps) iterate as long as their longest ray, not as long as the sums of
// their nested loops (llvmpipe counts those against its limit).
void avos_walkPieces(avos_real D, avos_real bound, inout avos_PiecewiseRay ray)
{
  avos_Walk walk = avos_startWalk(D);
  avos_real begin;
  avos_real end;
  int kept; // unused: every visible and kept part alike
  avos_CellWalk cells = avos_startCells(avos_real(0.0), avos_real(0.0)); // none yet
  avos_PieceWalk pieces;
  bool inCell = false;
  for (;;)
  {
    if (inCell && pieces.Next <= pieces.Last - pieces.First)
    {
      avos_nextPiece(pieces, ray);
      if (ray.Failed || ray.T <= bound)
      {
        break;
      }
      continue;
    }
    if (inCell && pieces.Stretch + 1 < pieces.Stretches)
    {
      avos_startStretch(pieces);
      continue;
    }
    ivec3 cell;
    avos_real t0;
    avos_real t1;
    if (avos_nextCell(cells, cell, t0, t1))
    {
      inCell = avos_startCell(pieces, cell, t0, t1);
      continue;
    }
    inCell = false;
    if (!avos_nextPart(walk, D, begin, end, kept))
    {
      break;
    }
    cells = avos_startCells(begin, end);
  }
}

avos_PiecewiseRay avos_startRay(avos_real L, float tolerance)
{
  avos_PiecewiseRay ray;
  ray.Colour = avos_real3(0.0);
  ray.T = avos_real(1.0);
  ray.InverseL = L > avos_real(0.0) ? avos_real(1.0) / L : avos_real(0.0);
  ray.Budget = avos_real(0.6) * avos_real(tolerance);
  ray.Failed = false;
  return ray;
}

// The piecewise method over the visible parts of [0, D] (IntegratePiecewise
// over the empty-space segments). Alpha < 0: a piece beyond its
// sub-interval bound.
vec4 avos_piecewise(avos_real D, float tolerance, bool earlyTermination)
{
  avos_real lastEnd;
  int parts;
  avos_real L = avos_visibleLength(D, lastEnd, parts);
  if (!(L > avos_real(0.0)))
  {
    return vec4(0.0);
  }
  avos_PiecewiseRay ray = avos_startRay(L, tolerance);
  avos_real bound = earlyTermination
    ? avos_real(0.15) * avos_real(tolerance) / max(avos_real(1.0), avos_real(avos_maximumColour))
    : avos_real(-1.0);
  avos_walkPieces(D, bound, ray);
  if (ray.Failed)
  {
    return vec4(0.0, 0.0, 0.0, -1.0);
  }
  float alpha = float(avos_real(1.0) - ray.T);
  return vec4(clamp(vec3(ray.Colour), vec3(0.0), vec3(alpha)), alpha);
}

// The additive (avos_blend 3) and average (4) projections as the CPU mapper
// shows them: grey, clamped to [0, 1], opaque wherever the ray meets the
// volume (the average: the range). Alpha < 0: an average beyond its bound
// of sub-intervals.
vec4 avos_accumulation(avos_real D)
{
  avos_PiecewiseRay ray = avos_startRay(avos_real(0.0), avos_tolerance);
  avos_walkPieces(D, avos_real(-1.0), ray);
  if (ray.Failed)
  {
    return vec4(0.0, 0.0, 0.0, -1.0);
  }
  if (avos_blend == 4 && !(ray.Colour.y > avos_real(0.0)))
  {
    return vec4(0.0);
  }
  avos_real value = avos_blend == 3 ? ray.Colour.x : ray.Colour.x / ray.Colour.y;
  float v = clamp(float(value), 0.0, 1.0);
  return vec4(v, v, v, 1.0);
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

// The kept parts of [0, avos_rayExtent] (numerics::ClipRegion::Kept's
// cropping): the ray cut where it crosses the six cropping planes (grid
// coordinates), each piece kept when the region of its middle is one of
// avos_cropFlags' 27, adjacent kept pieces merged.
void avos_keepParts()
{
  avos_real D = avos_rayExtent;
  avos_keptCount = 1;
  avos_kept[0] = avos_real2(avos_real(0.0), D);
  if (avos_cropping == 0)
  {
    return;
  }
  avos_real3 lo = avos_join(avos_cropMin, avos_cropMinLo);
  avos_real3 hi = avos_join(avos_cropMax, avos_cropMaxLo);
  // The crossings of the six planes inside (0, D), the others moved to D
  // (empty pieces), sorted by a network of compare-exchanges on scalars
  // (an insertion sort of an fp64 array lost values on llvmpipe).
  avos_real c[6];
  for (int a = 0; a < 3; ++a)
  {
    avos_real d = avos_rayDirection[a];
    avos_real tl = d != avos_real(0.0) ? (lo[a] - avos_rayOrigin[a]) / d : D;
    avos_real th = d != avos_real(0.0) ? (hi[a] - avos_rayOrigin[a]) / d : D;
    c[2 * a] = tl > avos_real(0.0) && tl < D ? tl : D;
    c[2 * a + 1] = th > avos_real(0.0) && th < D ? th : D;
  }
  avos_real c0 = c[0];
  avos_real c1 = c[1];
  avos_real c2 = c[2];
  avos_real c3 = c[3];
  avos_real c4 = c[4];
  avos_real c5 = c[5];
  avos_real x;
#define AVOS_ORDER(p, q)                                                                           \
  x = min(p, q);                                                                                   \
  q = max(p, q);                                                                                   \
  p = x;
  AVOS_ORDER(c0, c5) AVOS_ORDER(c1, c3) AVOS_ORDER(c2, c4) AVOS_ORDER(c1, c2) AVOS_ORDER(c3, c4)
  AVOS_ORDER(c0, c3) AVOS_ORDER(c2, c5) AVOS_ORDER(c0, c1) AVOS_ORDER(c2, c3) AVOS_ORDER(c4, c5)
  AVOS_ORDER(c1, c2) AVOS_ORDER(c3, c4)
  avos_real cuts[8] = avos_real[8](avos_real(0.0), c0, c1, c2, c3, c4, c5, D);
  int n = 8;
  avos_keptCount = 0;
  for (int i = 0; i + 1 < n; ++i)
  {
    avos_real a = cuts[i];
    avos_real b = cuts[i + 1];
    avos_real3 p = avos_rayOrigin + (avos_real(0.5) * (a + b)) * avos_rayDirection;
    int region = 0;
    int weight = 1;
    for (int k = 0; k < 3; ++k)
    {
      region += (p[k] < lo[k] ? 0 : (p[k] > hi[k] ? 2 : 1)) * weight;
      weight *= 3;
    }
    if (!(b > a) || ((avos_cropFlags >> region) & 1) == 0)
    {
      continue;
    }
    if (avos_keptCount > 0 && avos_kept[avos_keptCount - 1].y >= a)
    {
      avos_kept[avos_keptCount - 1].y = b; // adjacent kept regions: one part
    }
    else
    {
      avos_kept[avos_keptCount++] = avos_real2(a, b);
    }
  }
}

// The ray through this fragment's pixel centre from the near plane to the
// depth buffer (as vtkAdaptiveVolumeMapper casts it), clipped to the grid's
// box [0, n - 1] and to the clipping planes. False when nothing is left. Its points are affine in
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
  // The clipping planes keep normal . x + offset >= 0 (numerics::ClipRegion's
  // Kept): one interval, the ray starting at its entry (VTK's mappers start
  // a clipped ray there, and so do vtkAdaptiveVolumeMapper's).
  for (int i = 0; i < avos_clipPlaneCount; ++i)
  {
    avos_real3 normal = avos_join(avos_clipPlanes[i].xyz, avos_clipPlanesLo[i].xyz);
    avos_real a = dot(normal, centre) + avos_join(avos_clipPlanes[i].w, avos_clipPlanesLo[i].w);
    avos_real b = dot(normal, direction);
    if (b > avos_real(0.0))
    {
      u0 = max(u0, -a / b);
    }
    else if (b < avos_real(0.0))
    {
      u1 = min(u1, -a / b);
    }
    else if (a < avos_real(0.0))
    {
      return false;
    }
  }
  if (!(u1 > u0))
  {
    return false;
  }
  avos_rayOrigin = centre + u0 * direction;
  avos_rayDirection = direction;
  avos_toViewer = -normalize(avos_toWorld(avos_gridToWorld, vec4(vec3(direction), 0.0)));
  avos_walkOrigin = avos_real(avos_walkScale) * avos_rayOrigin;
  avos_walkDirection = avos_real(avos_walkScale) * direction;
  avos_rayEntry = float(tc + u0);
  avos_rayExtent = u1 - u0;
  avos_rayLength = float(avos_rayExtent);
  avos_keepParts();
  return avos_keptCount > 0;
}

vec4 avos_result;

// Whether the texture holds the whole volume (a texel per point, or per cell
// for cell scalars): VTK renders a volume split into partitions one block
// at a time, each with a texture of its own, which the rays cannot read.
bool avos_wholeVolume()
{
  ivec3 texels = ivec3(avos_dimensions) - (avos_fieldKind >= 2 ? ivec3(1) : ivec3(0));
  return textureSize(in_volume[0], 0) == texels;
}

// Casts this fragment's ray with the chosen method into avos_result
// (premultiplied RGBA over black); a volume not held whole is reported as a
// failed ray (alpha -1), never drawn from a block.
void avos_castRay()
{
  avos_channel = avos_component;
  avos_samples = 0;
  avos_attempts = 0;
  avos_result = vec4(0.0);
  if (!avos_wholeVolume())
  {
    avos_rayEntry = -1.0;
    avos_rayLength = 0.0;
    avos_result = vec4(0.0, 0.0, 0.0, -1.0);
    return;
  }
  if (!avos_setUpRay())
  {
    return;
  }
  // What the rest of a ray can add to any channel is at most T max(1, max C).
  float budget = 0.2 * avos_tolerance / max(1.0, avos_maximumColour);
  if (avos_blend == 1 || avos_blend == 2)
  {
    avos_result = avos_projection(avos_rayExtent, avos_blend == 1);
  }
  else if (avos_blend != 0)
  {
    avos_result = avos_accumulation(avos_rayExtent);
  }
  else if (avos_method == 3)
  {
    avos_result = avos_piecewise(avos_rayExtent, avos_tolerance, avos_earlyTermination != 0);
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
