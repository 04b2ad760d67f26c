/**
 * @class   vtkAdaptiveVolumeMapper
 * @brief   CPU ray casting mapper that integrates to a requested accuracy
 *
 * vtkAdaptiveVolumeMapper renders vtkImageData of 1 to 4 components with the
 * emission-absorption model and chooses its steps along each ray to meet an
 * error tolerance, instead of taking a fixed sample distance: the iterative
 * adaptive Simpson rule of Campagnolo, Celes and de Figueiredo, "Accurate
 * Volume Rendering based on Adaptive Numerical Integration" (SIBGRAPI 2015),
 * with the inner (optical depth) and outer (colour) integrals stepped in
 * consonance, coupled or decoupled. A Riemann sum (VTK's usual fixed step)
 * and a reference evaluator (error below 1e-6) are available for comparison.
 *
 * Units. Steps and tolerances are in voxel units: one voxel unit is the
 * world-space length of the shortest grid step (the smallest spacing, times
 * the vtkVolume's scale). Rays are cast through pixel centres, and the
 * result is RGB = integrated colour I, A = 1 - T over a black background,
 * composited over the scene.
 *
 * The field, as VTK's GPU mapper reads the scalars. Point scalars with the
 * property's linear interpolation are interpolated trilinearly; with
 * nearest interpolation (vtkVolumeProperty's default) each point's value
 * fills the part of the box nearest to it. Cell scalars with nearest
 * interpolation are constant on each cell; with linear interpolation they
 * are interpolated trilinearly between the cells' centres, and constant
 * across the outer half cells along the box's normal (a texture clamped to
 * its edge). Each is trilinear or constant on the cells of the point grid
 * or of that grid refined by 2, so every method integrates it as it does
 * the point scalars' (the piecewise method within eps, a field constant per
 * cell in one piece per region); only point scalars with linear
 * interpolation are shaded.
 *
 * Components. Scalars of 2 to 4 components are read as VTK's mappers read
 * them, each component interpolated as one would be. Independent
 * components (the property's default) each take the colour, scalar
 * opacity, unit distance and weight of their index, and the volume is
 * their mixture: its extinction the sum of the components' weighted
 * extinctions, its emission the sum of their weighted emissions
 * (avos/numerics/Mixture.h). Where at most one component shows this is
 * VTK's image; where several show together VTK's mappers average their
 * opacities per sample (sum a_k^2 / sum w_k a_k), which no extinction
 * represents, while here densities add. Dependent components: two, the
 * colour function of the first scalar and the opacity function of the
 * second; four (unsigned char), RGB = the first three / 255 and the opacity
 * function of the fourth. Every method takes them, the piecewise method
 * within eps; projections, shading and gradient opacity of several
 * components are refused.
 *
 * Opacity model. With SetOpacityModelToVTK() (the default) the scalar
 * opacity function is VTK's: an opacity accumulated over the property's
 * ScalarOpacityUnitDistance (world units), i.e. an extinction
 * tau = -ln(1 - alpha) / unit distance. With SetOpacityModelToExtinction()
 * the function's value is the extinction tau per voxel unit (the paper's
 * model, the .tf1d files' meaning).
 *
 * Work skipped: blocks of 4^3 cells that the transfer function maps to
 * tau = 0 (their value ranges are rebuilt when the data changes, their
 * visibility when the property does), the rest of a ray once what it can
 * still add is below a fifth of the tolerance, rays that miss the volume's
 * box, and the whole ray cast when nothing that affects the image changed
 * (the last image is drawn again). Opaque geometry is honoured through the
 * depth buffer: rays stop at it.
 *
 * Clipping planes (the mapper's, in world coordinates; each keeps the side
 * its normal points to) and cropping (VTK's 27 regions and flags, planes in
 * the volume's coordinates) cut every ray exactly where it crosses them: the
 * error-controlled methods integrate exactly the kept part, within their
 * tolerance; the Riemann sum starts a new ray at each kept part's entry, as
 * VTK's mappers do at a clipping plane.
 *
 * Blend modes: composite (the integral above), and the maximum and minimum
 * intensity projections, exact: the extremum of the trilinear field along
 * the ray (a cubic in each cell, so at a cell face or a root of its
 * derivative; VTK's mappers take the extremum of samples and miss peaks
 * between them), shown as VTK shows a projection: the colour there times the
 * opacity function's value there (clamped to [0, 1]), that value as alpha.
 * Additive and average intensity, with the meaning VTK's GPU mapper gives
 * them, integrated instead of sampled (avos/numerics/Accumulation.h): the
 * integral of the extinction times the scalar normalised to the data's range
 * (exact), and the mean of the step-corrected opacity times the normalised
 * scalar over the part of the ray whose scalar lies in AverageIPScalarRange
 * (within the tolerance); grey, opaque where the ray meets the volume (the
 * range).
 *
 * Gradient opacity (the first component's): the extinction times G(g), g
 * the magnitude of the exact gradient of the trilinear field in scalar
 * units per world unit, in both opacity models (avos/numerics/
 * GradientOpacity.h: VTK's mappers multiply a sample's step-corrected
 * opacity by G, whose limit as the step shrinks is that extinction; their
 * gradients are finite differences, VTK's GPU mapper's in scalar units per
 * average voxel spacing, divided by a quarter of the data's range and
 * clamped to 1). Every method takes it, the piecewise method and the
 * reference with a proven error (avos/numerics/PiecewiseGradientOpacity.h:
 * the extinction is then not a polynomial along a piece, it is enclosed).
 * A curved G (a Hermite curve, a log scale) is linearised by the piecewise
 * method within avos::GradientShare of its tolerance (a proven bound; the
 * rays integrated to the rest) and resampled by the other methods, the
 * reference included, with a warning. Projections and fields constant per
 * cell refuse it.
 *
 * Shading (the property's Shade, ambient, diffuse, specular and specular
 * power, the renderer's switched-on lights: directional, and positional with
 * their attenuation and spot cone as VTK's GPU mapper applies them): the
 * emission is lit as VTK's mappers light a sample (Blinn-Phong,
 * avos/numerics/Shading.h), with the exact gradient of the trilinear field
 * at the sample, not VTK's precomputed, quantised normals. The adaptive
 * methods control the error of the lit integrand; the piecewise method
 * proves it (avos/numerics/PiecewiseShading.h). The projections refuse
 * shading, and so does a positional light whose constant attenuation is 0
 * (unbounded at the light).
 *
 * Work is spread over vtkSMPTools threads by tiles of 16x16 pixels. Not
 * supported (an error says so and nothing is drawn): more than 4
 * components, 3 dependent ones, shading other than point scalars of one
 * component with linear interpolation, the isosurface and slice blend
 * modes, clipping planes with a transform, cropping of inputs with a
 * direction matrix or negative spacing.
 *
 * @sa vtkFixedPointVolumeRayCastMapper vtkGPUVolumeRayCastMapper
 */
#ifndef vtkAdaptiveVolumeMapper_h
#define vtkAdaptiveVolumeMapper_h

#include "avosRenderingAdaptiveVolumeModule.h" // For export macro
#include "vtkVolumeMapper.h"

#include <memory> // For std::unique_ptr

class vtkImageData;
class vtkRayCastImageDisplayHelper;
class vtkTable;
class vtkVolumeProperty;

class AVOSRENDERINGADAPTIVEVOLUME_EXPORT vtkAdaptiveVolumeMapper : public vtkVolumeMapper
{
public:
  static vtkAdaptiveVolumeMapper* New();
  vtkTypeMacro(vtkAdaptiveVolumeMapper, vtkVolumeMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  enum IntegrationMethods
  {
    RIEMANN = 0,        // right-hand Riemann sum, step SampleDistance, T *= exp(-tau h)
    ADAPTIVE_COUPLED,   // the paper's adaptive Simpson, outer step restarted from the inner one
    ADAPTIVE_DECOUPLED, // the paper's adaptive Simpson, outer step carried on
    REFERENCE,          // exact to 1e-9 (the piecewise method at 1e-10, shaded too; VTK's
                        // curved functions converted within a proven 1e-7 to 1e-5)
    PIECEWISE_ADAPTIVE  // smooth pieces between cell faces and knot crossings, eps on any TF
  };

  ///@{
  /**
   * How the volume rendering integral is evaluated along each ray. Default
   * ADAPTIVE_COUPLED (the paper's method).
   *
   * Which to choose: PIECEWISE_ADAPTIVE when the tolerance must hold
   * whatever the transfer function (thin layers, spikes, jumps: no step
   * crosses a knot or a cell face, so nothing hides between samples; the
   * optical depth is exact in the extinction model; no step to tune, only
   * the Tolerance, within [1e-12, 1], or [8e-12, 1] in VTK's opacity model).
   * ADAPTIVE_COUPLED / DECOUPLED reproduce the paper (their error estimate
   * can miss features narrower than MaximumStep). RIEMANN for VTK's
   * fixed-step behaviour. REFERENCE for ground truth.
   */
  vtkSetClampMacro(IntegrationMethod, int, RIEMANN, PIECEWISE_ADAPTIVE);
  vtkGetMacro(IntegrationMethod, int);
  void SetIntegrationMethodToRiemann() { this->SetIntegrationMethod(RIEMANN); }
  void SetIntegrationMethodToAdaptiveCoupled() { this->SetIntegrationMethod(ADAPTIVE_COUPLED); }
  void SetIntegrationMethodToAdaptiveDecoupled() { this->SetIntegrationMethod(ADAPTIVE_DECOUPLED); }
  void SetIntegrationMethodToReference() { this->SetIntegrationMethod(REFERENCE); }
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

  enum VectorModes
  {
    DISABLED = -1, // every component, as the property reads them
    MAGNITUDE = 0, // the Euclidean norm of the components
    COMPONENT = 1  // the component VectorComponent alone
  };

  ///@{
  /**
   * How scalars of several components are read, as vtkSmartVolumeMapper's
   * VectorMode (ParaView sets it from the colour map's vector mode). DISABLED
   * (the default) renders every component as the property says
   * (independent or dependent components). MAGNITUDE renders the Euclidean
   * norm of each tuple, one scalar through the property's first functions
   * (the norms are a float copy of the scalars, kept until they change: the
   * only copy the mapper makes). COMPONENT renders the component
   * VectorComponent (the last one where there are fewer), read in place,
   * through the property's first functions, where VTK's smart mapper copies
   * them onto that component of the property. Scalars of one component are
   * rendered as they are in every mode.
   */
  vtkSetClampMacro(VectorMode, int, DISABLED, COMPONENT);
  vtkGetMacro(VectorMode, int);
  vtkSetClampMacro(VectorComponent, int, 0, 3);
  vtkGetMacro(VectorComponent, int);
  ///@}

  ///@{
  /**
   * Adaptive methods: error tolerance eps per RGBA channel (default 0.01),
   * initial, minimum and maximum step in voxel units (defaults 0.5, 0.1, 2,
   * the paper's). Checked at render time: eps > 0, and the steps within
   * [0.001, 1000] with MinimumStep <= MaximumStep (at most 1000 steps per
   * voxel: every ray's work is bounded).
   */
  vtkSetMacro(Tolerance, double);
  vtkGetMacro(Tolerance, double);
  vtkSetMacro(InitialStep, double);
  vtkGetMacro(InitialStep, double);
  vtkSetMacro(MinimumStep, double);
  vtkGetMacro(MinimumStep, double);
  vtkSetMacro(MaximumStep, double);
  vtkGetMacro(MaximumStep, double);
  ///@}

  ///@{
  /**
   * The range every step (SampleDistance, InitialStep, MinimumStep,
   * MaximumStep) must lie in, in voxel units: at most 1000 samples per voxel,
   * so that no setting makes a ray's work unbounded.
   */
  static double GetSmallestStep() { return 1e-3; }
  static double GetLargestStep() { return 1e3; }
  ///@}

  ///@{
  /**
   * Riemann method: the step in voxel units (default 0.5), within
   * [0.001, 1000] (checked at render time).
   */
  vtkSetMacro(SampleDistance, double);
  vtkGetMacro(SampleDistance, double);
  ///@}

  ///@{
  /**
   * Skip blocks the transfer function makes transparent (default on). Off
   * is only useful to measure what skipping saves: the image is the same.
   */
  vtkSetMacro(EmptySpaceSkipping, vtkTypeBool);
  vtkGetMacro(EmptySpaceSkipping, vtkTypeBool);
  vtkBooleanMacro(EmptySpaceSkipping, vtkTypeBool);
  ///@}

  ///@{
  /**
   * One ray every ImageSampleDistance pixels in x and y (default 1, clamped
   * to [1, 100]); the smaller image is stretched over the viewport, as
   * vtkFixedPointVolumeRayCastMapper does. With AutoAdjustSampleDistances on
   * (the default) the distance is chosen per frame instead, within
   * [MinimumImageSampleDistance, MaximumImageSampleDistance] (defaults 1 and
   * 10), so that the ray cast fits the time the renderer allocates to the
   * volume (vtkProp::GetAllocatedRenderTime(): about 1 / DesiredUpdateRate
   * while interacting, hours for a still render). The cast time is taken
   * to grow with the number of rays; estimates within 10 % of the last
   * distance keep it, so an unchanged frame is not cast again.
   * GetLastImageSampleDistance() is the distance the last image was cast
   * with.
   */
  vtkSetClampMacro(ImageSampleDistance, double, 1.0, 100.0);
  vtkGetMacro(ImageSampleDistance, double);
  vtkSetClampMacro(MinimumImageSampleDistance, double, 1.0, 100.0);
  vtkGetMacro(MinimumImageSampleDistance, double);
  vtkSetClampMacro(MaximumImageSampleDistance, double, 1.0, 100.0);
  vtkGetMacro(MaximumImageSampleDistance, double);
  vtkSetMacro(AutoAdjustSampleDistances, vtkTypeBool);
  vtkGetMacro(AutoAdjustSampleDistances, vtkTypeBool);
  vtkBooleanMacro(AutoAdjustSampleDistances, vtkTypeBool);
  vtkGetMacro(LastImageSampleDistance, double);
  ///@}

  /**
   * The image of the last render: viewport-sized (divided by the image
   * sample distance, rounded up, when it is above 1), float RGBA point scalars
   * named "RGBA" (RGB = I premultiplied by opacity, A = 1 - T, black
   * background), row 0 at the bottom. Empty before the first render and
   * after a render that failed.
   */
  vtkImageData* GetRenderedImage();

  ///@{
  /**
   * Statistics of the last ray cast: wall time of the whole Render call in
   * seconds, rays that entered the volume's box, samples (transfer-function
   * evaluations) per such ray, steps rejected by the error control, and for
   * the piecewise methods (PIECEWISE_ADAPTIVE, REFERENCE unshaded) the cells
   * with visible scalars and the smooth pieces per ray.
   * LastRenderReused is true when nothing had changed and the previous image
   * was drawn again (the other figures then describe that image's ray cast).
   */
  vtkGetMacro(LastRenderTime, double);
  vtkGetMacro(RaysCast, vtkIdType);
  vtkGetMacro(MeanSamplesPerRay, double);
  vtkGetMacro(MaximumSamplesPerRay, vtkIdType);
  vtkGetMacro(RejectedSteps, vtkIdType);
  vtkGetMacro(MeanCellsPerRay, double);
  vtkGetMacro(MeanPiecesPerRay, double);
  vtkGetMacro(LastRenderReused, bool);
  ///@}

  /**
   * Number of 4^3-cell blocks and how many of them the current transfer
   * function leaves visible (after a render).
   */
  vtkIdType GetNumberOfBlocks();
  vtkIdType GetNumberOfVisibleBlocks();

  /**
   * Casts pixel (x, y) of the last render again (its data, camera, method
   * and transfer function) and fills `steps` with one row per accepted step
   * of the outer integral: "Start" and "Length" along the ray, in voxel
   * units from where it enters the volume's box, and "Opacity", the 1 - T
   * reached at the step's end (the paper's Figure 6). Riemann gives its
   * uniform steps, the piecewise method its smooth pieces. False, with an
   * empty table, when there was no render, the method is the reference, the pixel is outside the
   * image, or its ray misses the volume's box.
   */
  bool TraceRay(int x, int y, vtkTable* steps);

  void Render(vtkRenderer* ren, vtkVolume* vol) override;
  void ReleaseGraphicsResources(vtkWindow* win) override;

protected:
  vtkAdaptiveVolumeMapper();
  ~vtkAdaptiveVolumeMapper() override;

  ///@{
  /**
   * The stages of Render, in the order data flows, as
   * vtkFixedPointVolumeRayCastMapper's: the settings, the input, its grid in
   * world space and the clip region, what depends on the scalars (the
   * empty-space map's ranges), what depends on the property (the transfer
   * function, the blocks' visibility, the shading, the pieces), the kernels'
   * tables, the frame (image size, depth buffer, rays, footprint), the ray
   * cast (skipped when nothing the last image depends on changed), the
   * display. Each stage keeps its caches with the timestamps that say when to
   * rebuild them, and returns false, with an error where something is wrong,
   * when the frame cannot be drawn.
   */
  bool ValidateSettings();
  vtkImageData* UpdateInput();
  /// The scalars the vector mode makes of the input's (the magnitude's
  /// copy, or one component: internals' Component).
  vtkDataArray* ScalarsOfVectorMode(vtkDataArray* scalars);
  bool UpdateGeometry(vtkImageData* input, vtkVolume* vol);
  bool UpdateScalars(vtkVolume* vol);
  bool UpdateProperty(vtkRenderer* ren, vtkVolume* vol);
  bool UpdateTransferFunction(vtkVolumeProperty* property);
  bool UpdateGradientOpacity(vtkVolumeProperty* property);
  bool UpdatePieces();
  bool UpdateKernelTables();
  bool SetUpFrame(vtkRenderer* ren, vtkVolume* vol);
  bool CastFrame(vtkRenderer* ren);
  void DisplayFrame(vtkRenderer* ren, vtkVolume* vol);
  ///@}

  /// The image sample distance of the next frame: ImageSampleDistance, or
  /// with AutoAdjustSampleDistances what fits the volume's allocated render
  /// time at the last cast's speed.
  double NextImageSampleDistance(vtkVolume* vol) const;
  /// The cast's method from the settings and the stages' tables.
  void SetUpMethod();
  void PublishStatistics(vtkIdType rays, vtkIdType samples, vtkIdType maximumSamples,
    vtkIdType rejected, vtkIdType cells, vtkIdType pieces);
  /// The float image as the display helper's 16-bit RGBA.
  void ConvertForDisplay(const float* image, std::size_t values);

  int IntegrationMethod = ADAPTIVE_COUPLED;
  int OpacityModel = VTK_OPACITY;
  int VectorMode = DISABLED;
  int VectorComponent = 0;
  double Tolerance = 0.01;
  double InitialStep = 0.5;
  double MinimumStep = 0.1;
  double MaximumStep = 2.0;
  double SampleDistance = 0.5;
  vtkTypeBool EmptySpaceSkipping = 1;
  double ImageSampleDistance = 1.0;
  double MinimumImageSampleDistance = 1.0;
  double MaximumImageSampleDistance = 10.0;
  vtkTypeBool AutoAdjustSampleDistances = 1;
  double LastImageSampleDistance = 1.0;

  double LastRenderTime = 0.0;
  vtkIdType RaysCast = 0;
  double MeanSamplesPerRay = 0.0;
  vtkIdType MaximumSamplesPerRay = 0;
  vtkIdType RejectedSteps = 0;
  double MeanCellsPerRay = 0.0;
  double MeanPiecesPerRay = 0.0;
  bool LastRenderReused = false;

private:
  vtkAdaptiveVolumeMapper(const vtkAdaptiveVolumeMapper&) = delete;
  void operator=(const vtkAdaptiveVolumeMapper&) = delete;

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
