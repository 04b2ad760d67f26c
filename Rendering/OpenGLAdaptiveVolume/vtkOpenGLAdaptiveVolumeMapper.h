/**
 * @class   vtkOpenGLAdaptiveVolumeMapper
 * @brief   GPU ray casting with the adaptive Simpson rule, inside VTK's GPU ray caster
 *
 * vtkOpenGLAdaptiveVolumeMapper is the GPU version (GLSL, single precision)
 * of the adaptive integration of Campagnolo, Celes and de Figueiredo,
 * "Accurate Volume Rendering based on Adaptive Numerical Integration"
 * (SIBGRAPI 2015): the paper's Algorithm 3 with its inner (optical depth)
 * and outer (colour) integrals stepped in consonance, coupled or decoupled,
 * the Riemann sum as the fixed-step baseline, and the project's piecewise
 * method (PIECEWISE_ADAPTIVE, see below), whose error is proven. It is a
 * vtkOpenGLGPUVolumeRayCastMapper whose fragment shader casts each pixel's
 * ray with that integrator instead of VTK's loop, so it composes with what
 * VTK's GPU volume rendering does around the ray: opaque geometry through
 * the depth buffer, other props, interaction, RenderToImage.
 *
 * The integrals are those of vtkAdaptiveVolumeMapper (the CPU mapper, in
 * double), statement for statement: the same rays (through pixel centres,
 * from the near plane to the depth buffer, clipped to the grid's box, t in
 * voxel units), the same field (texels fetched and interpolated in
 * the shader, not by the texture unit, whose 8-bit filtering errs by 5e-3 on
 * llvmpipe), the same piecewise-linear transfer function (knots as uniforms,
 * searched exactly, not VTK's 1D tables), the same opacity models, step
 * control, error estimates and early termination. Its tests bound the
 * difference to the CPU core in double on the same rays.
 *
 * PIECEWISE_ADAPTIVE is numerics::IntegratePiecewise in double where the
 * context has GL_ARB_gpu_shader_fp64 (in float elsewhere, below): the ray cut at cell
 * faces, at the extrema of each cell's cubic and at its crossings of the
 * knots of numerics::PiecewiseTransferFunction (VTK's alpha model within a
 * relative eps / 8, as on the CPU), the optical depth of each piece in
 * closed form, the colour integral's one non-closed term J by the midpoint
 * of its bounds (second mean value theorem) or the power series of the
 * transmittance truncated within a proven bound (at most 16 terms a
 * sub-interval, where the CPU takes 40), early termination within 0.15
 * eps. VTK's colour and opacity functions are converted as
 * vtkAdaptiveVolumeMapper's piecewise method converts them: within shares
 * of eps where they are not piecewise linear (other colour spaces, Hermite
 * curves, log scales), the rays integrated to the rest. Every channel of every pixel lies within
 * eps (from 1e-5 to 1) of the integral of VTK's transfer function as the shader's float uniforms
 * hold it (relative rounding 6e-8, which moves a pixel by about 1e-7).
 * Its float path (a context without fp64, or UseDoublePrecision off) is the
 * same code with positions, pieces and sums in float: the certificate
 * covers the method's truncations, not float rounding, so a pixel lies
 * within eps plus that rounding: measured at most 0.73 eps at eps 1e-4 (7.3e-5 on
 * thin layers of 1/255 voxel, 5.9e-5 on Bonsai), at most 0.15 eps from
 * 1e-3 on; the tests hold it to 2 eps, and it refuses eps below 1e-4.
 *
 * Blend modes: composite (the integral), and the maximum and minimum
 * intensity projections, exact as vtkAdaptiveVolumeMapper's: the extremum of
 * the trilinear field along the ray (a cubic in each cell, at a cell face
 * or a root of its derivative, in double where the context has fp64),
 * shown as the colour there times the opacity function's value there
 * (clamped to [0, 1]), that value as alpha. VTK's GPU mapper takes the
 * extremum of samples and misses peaks between them. The additive and
 * average intensity projections (where the context has fp64) are
 * vtkAdaptiveVolumeMapper's, VTK's GPU mapper's meaning integrated along the
 * ray instead of sampled (numerics' Accumulation.h): additive, the integral
 * of the extinction times the scalar normalised to the data's range, exact
 * on each piece of the transfer function (7-point Gauss-Legendre on a
 * polynomial); average, the mean over the ray's length inside
 * AverageIPScalarRange of the opacity of a slab of RiemannStep times that
 * normalised scalar, within the tolerance (Gauss-Legendre 8 against 4,
 * halving); grey, opaque where the ray meets the volume (the range).
 *
 * Clipping planes (up to 6, world coordinates, each keeping the side its
 * normal points to) and cropping (VTK's 27 regions and flags) cut every ray
 * exactly where vtkAdaptiveVolumeMapper cuts it; the Riemann sum starts
 * again at each kept part's entry (as VTK's mappers start a clipped ray).
 * The superclass builds its shader without them.
 *
 * The field is the one vtkAdaptiveVolumeMapper integrates (VTK's GPU
 * mapper's reading of the scalars): point scalars trilinear (linear
 * interpolation) or each point's value on the part of the box nearest to it
 * (nearest, vtkVolumeProperty's default); cell scalars (a texel per cell, as
 * VTK uploads them) constant per cell (nearest) or trilinear between the
 * cells' centres (linear). Each is trilinear on the cells of the point grid
 * or of that grid refined by 2, which every method walks. A cell with a NaN
 * corner is empty (transparent) in every method, as on the CPU; the NaN
 * count is said once per change of the scalars.
 *
 * Supported: one-component point or cell scalars of every type VTK's GPU mapper
 * uploads (8-, 16-, 32- and 64-bit integers, signed or not, float,
 * double), read back exactly for 8- and 16-bit integers and for wider ones
 * whose range spans at most 2^20 (within float's rounding of the range
 * otherwise and for double, which VTK scales onto [0, 1] in float); 2 to 4
 * components (8- and 16-bit integers, float) in the composite blend,
 * unshaded, as the CPU mapper renders them: where one alone shows (the
 * others of weight 0 or transparent), by every method, that component's
 * channel with its transfer function, its weight in its extinction; their
 * mixture (numerics::MixtureTransferFunction: independent ones' extinctions
 * and emissions added, the dependent colour-and-opacity pair and RGBA) by
 * the sampled methods, every channel read at each sample; the
 * blend modes above (all of vtkVolumeMapper's but the isosurface and
 * slice blends), clipping planes, cropping, linear and nearest interpolation, 1D
 * transfer functions, shading in the sampled methods (Riemann, coupled,
 * decoupled): each sample lit by vtkAdaptiveVolumeMapper's rule
 * (numerics::ShadingModel: the exact gradient of the trilinear field,
 * Blinn-Phong with the property's coefficients, the renderer's switched-on
 * lights, directional, positional and spot, up to 8, two-sided or not,
 * ambient alone where the gradient vanishes, clamped), point scalars with
 * linear interpolation in the composite blend; gradient opacity in the
 * sampled methods (numerics::GradientOpacity: a sample's extinction times G
 * of the exact gradient's length in scalar units per world unit, G of up
 * to 128 pieces), as on the CPU. Refused with an error and nothing
 * drawn (never ignored): signed 8- and 16-bit scalars that reach -128 or
 * -32768 (VTK's normalised texture reads them as the next value up), other
 * scalar types, several components of which several show, or dependent
 * ones, in the piecewise method (vtkAdaptiveVolumeMapper integrates them),
 * the isosurface and slice blends, the
 * piecewise method and the additive and average projections without fp64,
 * cropping an input with a direction matrix or negative spacing, more than
 * 6 clipping planes or one with a transform, masks, jittering, the depth
 * pass, NATIVE transfer-function ranges, a vtkMultiVolume's further inputs,
 * shading in the piecewise method (the CPU mapper's certified lit colour is
 * not in the shader), more than 8 lights, gradient opacity in the piecewise method, projections
 * or other fields, 2D transfer functions, dual depth
 * peeling of volumes, invalid tolerances or steps, transfer functions with more pieces than the
 * GPU's uniform storage holds.
 *
 * Empty space is skipped exactly: blocks of 4^3 cells whose value range
 * the transfer function maps to zero opacity are left out of every ray (a
 * 3D texture of the blocks' visibility, rebuilt when the data or the
 * property changes), as vtkAdaptiveVolumeMapper does. The projections walk
 * every cell of the ray (a transparent block may hold the extremum).
 *
 * A ray that cannot be integrated (beyond the adaptive loop's bound of
 * attempts, or cut short by the OpenGL implementation: Mesa's llvmpipe ends
 * a shader's loops after 65535 iterations per group of fragments, which an
 * in-shader check detects) is drawn opaque magenta and reads -1 in the
 * validation image's alpha, never shown as a value.
 *
 * The mapper adds its shader replacements and custom uniforms to the
 * volume's vtkOpenGLShaderProperty: a vtkVolume rendered by this mapper
 * should not be shared with another GPU mapper.
 *
 * Validation. With RenderToImage on and a float depth image
 * (SetDepthImageScalarTypeToFloat()), SetImageQuantity() puts one float per
 * pixel into the depth image instead of the depth: a channel of the
 * integral, the ray's entry or length, or its sample count. The colour
 * image of an OpenGL framebuffer has 8 bits per channel; this is how the
 * tests compare single-precision results with the CPU core.
 *
 * @sa vtkAdaptiveVolumeMapper vtkOpenGLGPUVolumeRayCastMapper
 */
#ifndef vtkOpenGLAdaptiveVolumeMapper_h
#define vtkOpenGLAdaptiveVolumeMapper_h

#include "avosRenderingOpenGLAdaptiveVolumeModule.h" // For export macro
#include "vtkOpenGLGPUVolumeRayCastMapper.h"

#include <memory> // For std::unique_ptr
#include <string> // For std::string

class vtkDataArray;
class vtkMatrix4x4;
class vtkOpenGLShaderProperty;
class vtkUniforms;

class AVOSRENDERINGOPENGLADAPTIVEVOLUME_EXPORT vtkOpenGLAdaptiveVolumeMapper
  : public vtkOpenGLGPUVolumeRayCastMapper
{
public:
  static vtkOpenGLAdaptiveVolumeMapper* New();
  vtkTypeMacro(vtkOpenGLAdaptiveVolumeMapper, vtkOpenGLGPUVolumeRayCastMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum IntegrationMethods
  {
    RIEMANN = 0,        // right-hand Riemann sum, step RiemannStep, T *= exp(-tau h)
    ADAPTIVE_COUPLED,   // the paper's adaptive Simpson, outer step restarted from the inner one
    ADAPTIVE_DECOUPLED, // the paper's adaptive Simpson, outer step carried on
    PIECEWISE_ADAPTIVE  // pieces at cell faces and knot crossings, within eps (proven)
  };

  ///@{
  /**
   * How the volume rendering integral is evaluated along each ray. Default
   * ADAPTIVE_COUPLED (the paper's method); PIECEWISE_ADAPTIVE needs fp64.
   */
  vtkSetClampMacro(IntegrationMethod, int, RIEMANN, PIECEWISE_ADAPTIVE);
  vtkGetMacro(IntegrationMethod, int);
  void SetIntegrationMethodToRiemann() { this->SetIntegrationMethod(RIEMANN); }
  void SetIntegrationMethodToAdaptiveCoupled() { this->SetIntegrationMethod(ADAPTIVE_COUPLED); }
  void SetIntegrationMethodToAdaptiveDecoupled() { this->SetIntegrationMethod(ADAPTIVE_DECOUPLED); }
  void SetIntegrationMethodToPiecewiseAdaptive() { this->SetIntegrationMethod(PIECEWISE_ADAPTIVE); }
  const char* GetIntegrationMethodAsString();
  ///@}

  enum OpacityModels
  {
    VTK_OPACITY = 0,   // alpha per ScalarOpacityUnitDistance, as VTK's mappers
    EXTINCTION_OPACITY // tau per voxel unit, as the paper
  };

  ///@{
  /**
   * What the volume property's scalar opacity function means. Default
   * VTK_OPACITY.
   */
  vtkSetClampMacro(OpacityModel, int, VTK_OPACITY, EXTINCTION_OPACITY);
  vtkGetMacro(OpacityModel, int);
  void SetOpacityModelToVTK() { this->SetOpacityModel(VTK_OPACITY); }
  void SetOpacityModelToExtinction() { this->SetOpacityModel(EXTINCTION_OPACITY); }
  ///@}

  ///@{
  /**
   * Adaptive methods: error tolerance eps per RGBA channel (default 0.01,
   * within (0, 1], the piecewise method's within [1e-5, 1]; a fifth of it
   * bounds early termination, for Riemann too), initial, minimum and maximum
   * step in voxel units (defaults 0.5, 0.1, 2, the paper's). Riemann: its
   * step in voxel units (default 0.5). Every step lies in [0.001, 1000] with
   * MinimumStep <= MaximumStep (checked at render time: a ray's work is
   * bounded).
   */
  vtkSetMacro(Tolerance, double);
  vtkGetMacro(Tolerance, double);
  vtkSetMacro(InitialStep, double);
  vtkGetMacro(InitialStep, double);
  vtkSetMacro(MinimumStep, double);
  vtkGetMacro(MinimumStep, double);
  vtkSetMacro(MaximumStep, double);
  vtkGetMacro(MaximumStep, double);
  vtkSetMacro(RiemannStep, double);
  vtkGetMacro(RiemannStep, double);
  ///@}

  ///@{
  /**
   * Stop a ray once what it can still add to any channel is below a fifth
   * of the tolerance (default on).
   */
  vtkSetMacro(EarlyTermination, vtkTypeBool);
  vtkGetMacro(EarlyTermination, vtkTypeBool);
  vtkBooleanMacro(EarlyTermination, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Skip the blocks of 4^3 cells whose value range the transfer function
   * maps to zero opacity (default on): exact, since the trilinear field stays
   * inside a block's range. The ranges are rebuilt when the scalars change,
   * the blocks' visibility when the property, the opacity model or the voxel
   * size does.
   */
  vtkSetMacro(EmptySpaceSkipping, vtkTypeBool);
  vtkGetMacro(EmptySpaceSkipping, vtkTypeBool);
  vtkBooleanMacro(EmptySpaceSkipping, vtkTypeBool);
  ///@}

  enum ImageQuantities
  {
    DEPTH = 0, // VTK's own depth image
    RED,
    GREEN,
    BLUE,
    ALPHA,
    RAY_ENTRY,  // voxel units from the near plane to the box (-1: the ray misses it)
    RAY_LENGTH, // voxel units inside the box, up to the depth buffer
    SAMPLES     // transfer-function evaluations (projections, piecewise: cells examined)
  };

  ///@{
  /**
   * What the depth image of RenderToImage holds (default DEPTH, VTK's
   * meaning). Any other quantity needs a float depth image
   * (SetDepthImageScalarTypeToFloat()); rendering refuses it otherwise.
   */
  vtkSetClampMacro(ImageQuantity, int, DEPTH, SAMPLES);
  vtkGetMacro(ImageQuantity, int);
  ///@}

  /**
   * Whether the last render placed its rays and samples in double precision
   * (1: the context has GL_ARB_gpu_shader_fp64, core since OpenGL 4.0): the
   * ray set-up, the integration variable (step bounds, sample positions, the
   * visible parts) and the samples' grid positions; the samples' values and
   * the integrals' sums stay in float. Then the images agree with the CPU
   * core in double within the tolerance and a 99th percentile of 1.5e-6 on
   * the tests' scenes, rays within 3e-5 voxel. In float (0) a step's bounds
   * round by 1.5e-5 voxel at t = 256: a 99th percentile up to 3.4e-5 on
   * Bonsai at eps 1e-4, as the core compiled in float, and ray entries up to
   * 3.2e-4 voxel off at grazing faces.
   */
  vtkGetMacro(DoublePrecisionRays, vtkTypeBool);

  /**
   * The shader reads the whole volume from one texture: a volume split into
   * partitions is refused with an error and nothing drawn. This hides the
   * superclass's SetPartitions (not virtual); partitions set through a
   * vtkOpenGLGPUVolumeRayCastMapper pointer are caught by the shader, which
   * draws every ray as failed (magenta), never from a block.
   */
  void SetPartitions(unsigned short x, unsigned short y, unsigned short z);

  ///@{
  /**
   * Whether to use double precision where the context has it (default on).
   * Off, every method runs its float path, as on a context without fp64.
   */
  vtkSetMacro(UseDoublePrecision, vtkTypeBool);
  vtkGetMacro(UseDoublePrecision, vtkTypeBool);
  vtkBooleanMacro(UseDoublePrecision, vtkTypeBool);
  ///@}

  /**
   * Empty when the mapper can render its input with `property` now, else
   * why not (the message rendering reports). Also called by GPURender, which
   * also refuses what only the frame tells: clipping planes with a
   * transform and cropping that cannot be placed on the grid
   * (avos::ClipRegionOfMapper, as the CPU mapper), the piecewise method
   * without fp64, more pieces than the fragment uniforms hold.
   */
  std::string CheckRenderable(vtkRenderer* ren, vtkVolumeProperty* property);

  /**
   * Releases the blocks' texture with the superclass's resources.
   */
  void ReleaseGraphicsResources(vtkWindow* window) override;

protected:
  vtkOpenGLAdaptiveVolumeMapper();
  ~vtkOpenGLAdaptiveVolumeMapper() override;

  void GPURender(vtkRenderer* ren, vtkVolume* vol) override;

  ///@{
  /**
   * The stages of GPURender, in the order data flows: the frame checked and
   * prepared (CheckRenderable, the grid-to-world matrix and the voxel size,
   * the clipping planes, UpdateShading: the lights, UpdateGradientOpacity:
   * the gradient opacity function, then UpdateTransferFunction: the transfer function rebuilt
   * when the property changed, the piecewise method's pieces when it or the
   * tolerance did, their uniforms' room; an error message or empty), the
   * shader's replacements, the uniforms of the volume, of the transfer
   * function's pieces (and the piecewise method's), of the method, of the
   * shading and of the gradient opacity, the empty-space blocks' ranges
   * (rebuilt when the scalars change; their NaN count said once) and
   * texture (uploaded when the ranges or the transfer function change), the rays'
   * uniforms for this camera and the cuts' (clipping planes and cropping in
   * grid coordinates).
   */
  std::string PrepareFrame(
    vtkRenderer* ren, vtkVolume* vol, vtkMatrix4x4* gridToWorld, double& voxel);
  std::string UpdateShading(vtkRenderer* ren, vtkVolumeProperty* property);
  std::string UpdateGradientOpacity(vtkVolumeProperty* property);
  std::string UpdateTransferFunction(
    vtkVolumeProperty* property, vtkMatrix4x4* gridToWorld, double voxel);
  void AddShaderReplacements(vtkOpenGLShaderProperty* shaderProperty);
  void SetVolumeUniforms(vtkUniforms* uniforms);
  void SetPieceUniforms(vtkUniforms* uniforms);
  void SetPiecewiseUniforms(vtkUniforms* uniforms);
  void SetMethodUniforms(vtkUniforms* uniforms);
  void SetShadingUniforms(vtkUniforms* uniforms, vtkMatrix4x4* gridToWorld);
  void SetGradientOpacityUniforms(vtkUniforms* uniforms);
  void UpdateRanges();
  void UpdateBlocks(vtkRenderer* ren, vtkOpenGLShaderProperty* shaderProperty);
  void SetRayUniforms(
    vtkRenderer* ren, vtkUniforms* uniforms, vtkMatrix4x4* gridToWorld, double voxel);
  void SetCutUniforms(vtkUniforms* uniforms);
  ///@}

  ///@{
  /**
   * CheckRenderable's parts: the input (image data, point or cell scalars of one
   * component in a type the shader reads), VTK's mapper settings (blend
   * mode, the number of planes, masks, jittering, depth pass, range types, depth
   * peeling, the image quantity), the method's (tolerance, steps), those
   * that read the field's gradient (shading and gradient opacity: the
   * sampled methods take them on point scalars with linear interpolation, in
   * the composite blend). Each returns why not, or an empty string.
   */
  std::string CheckInput();
  std::string CheckVTKSettings(vtkRenderer* ren);
  std::string CheckMethodSettings();
  std::string CheckGradientSettings(vtkVolumeProperty* property);
  ///@}

  /**
   * The scalars rendered (point or cell scalars of 1 to 4 components, as CheckRenderable requires).
   */
  vtkDataArray* GetRenderedScalars();

  /**
   * The field the scalars make with `property`'s interpolation (the shader's
   * avos_fieldKind: 0 point scalars, linear; 1 point scalars, nearest; 2
   * cell scalars, nearest; 3 cell scalars, linear).
   */
  int ScalarFieldOf(vtkVolumeProperty* property);

  int IntegrationMethod = ADAPTIVE_COUPLED;
  int OpacityModel = VTK_OPACITY;
  double Tolerance = 0.01;
  double InitialStep = 0.5;
  double MinimumStep = 0.1;
  double MaximumStep = 2.0;
  double RiemannStep = 0.5;
  vtkTypeBool EarlyTermination = 1;
  int ImageQuantity = DEPTH;
  vtkTypeBool EmptySpaceSkipping = 1;
  vtkTypeBool DoublePrecisionRays = 0;
  vtkTypeBool UseDoublePrecision = 1;
  bool Partitioned = false; // SetPartitions asked for more than one block

private:
  vtkOpenGLAdaptiveVolumeMapper(const vtkOpenGLAdaptiveVolumeMapper&) = delete;
  void operator=(const vtkOpenGLAdaptiveVolumeMapper&) = delete;

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
