/**
 * @class   vtkVolumeOnSurfaceFilter
 * @brief   colours an isosurface with the volume seen through it (VoS^M)
 *
 * The Volume on Surface technique (VoS^M) of the paper in
 * ../shared/papers/volume-on-surface.txt, as a pipeline filter:
 * - cones construction: around each vertex normal, one cone per opening
 *   angle (default 20, 45 and 70 degrees) with RaysPerCone rays (default 4)
 *   equally spaced around it;
 * - cones oriented into the volume: the rule for an isosurface's normals is
 *   that they point to the side a visible vertex is seen from (vtkFlyingEdges3D's
 *   and vtkPolyDataNormals' do for the side they face; FlipNormals for
 *   surfaces whose normals point the other way), so the cones are built
 *   around the opposite of the normal, into the volume behind the surface;
 * - previsualization: every ray starts at its vertex and runs into the
 *   volume to its far boundary, integrated front to back from the vertex
 *   with the numerical core (the piecewise method by default, the Riemann
 *   sum of the paper's Levoy model, or the adaptive Simpson rule), with
 *   early ray termination; the RGBA of every ray is kept;
 * - vertex colour assignment: for the camera (SetCamera), each vertex takes
 *   the colour of its ray with the largest positive dot product with the
 *   observation line directed away from the observer (eye to vertex; the
 *   direction of projection for a parallel camera); vertices without such a
 *   ray get transparent black.
 * VolumeSide IN_FRONT_OF_SURFACE builds the cones around the normal itself
 * and integrates the volume between the vertex and the observer's side
 * instead (the observation line then runs from the vertex to the eye).
 *
 * The output is the input surface with three point arrays: "VoSColors"
 * (unsigned char RGBA: RGB = the integrated colour over black, A = opacity;
 * the active scalars), "VoSDisplayColors" (its RGB alone: the surface as the
 * paper draws it, opaque, showing the volume behind it as a ray cast over
 * black would; colour a polydata mapper by it with
 * SetScalarModeToUsePointFieldData and SelectColorArray, since RGBA scalars
 * are blended, multiplying the colour by its opacity once more) and "VoSRay"
 * (the index of the chosen ray, -1 for none).
 *
 * Interaction, as in the paper: the filter's modification time includes the
 * camera's, so a camera change re-executes it, but only the assignment runs
 * again (a few dot products per vertex: cheap enough for every frame). The
 * previsualization is redone only when the surface, the volume, the volume
 * property, a cone or integration parameter or, shaded, the lights changed.
 * GetNumberOfRaysCast() tells which happened in the last execution.
 *
 * Inputs: port 0 the isosurface (vtkPolyData with point normals; computed
 * with vtkPolyDataNormals when absent), port 1 the volume (vtkImageData;
 * SetVolumeConnection), read as vtkAdaptiveVolumeMapper reads it: its point
 * scalars, else its cell scalars, with the property's linear or nearest
 * interpolation, of 1 to 4 components (independent or dependent, unshaded
 * and without gradient opacity when several). Steps are in voxel units (the
 * smallest spacing), as in vtkAdaptiveVolumeMapper.
 *
 * The volume property's gradient opacity scales the extinction as in
 * vtkAdaptiveVolumeMapper (G of the exact gradient's magnitude, scalar units
 * per world unit; the piecewise method within Tolerance). With the
 * property's Shade on, each cone ray's emission is lit as
 * vtkAdaptiveVolumeMapper lights a ray's (Blinn-Phong on the exact gradient;
 * the piecewise method within Tolerance) by the switched-on lights of the
 * renderer given to SetRenderer, as seen along the ray itself: the ray
 * stands for the observation line it is chosen for. Where the renderer has
 * no light switched on yet and creates its own (AutomaticLightCreation, at
 * its first render), the rays take the headlight it creates: white, at the
 * camera. The lit colours depend on the lights: lights that follow the
 * camera (headlights, camera lights) change with every camera change, and
 * the cones are cast again then; with scene lights alone a camera change
 * only assigns colours.
 *
 * Pieces (distributed pipelines): the surface is the piece asked of this
 * filter, with its ghost cells passed through (each vertex is coloured
 * alike on every piece that holds it); the volume is requested whole on
 * every piece, since a vertex's rays leave the piece's part of the volume:
 * each piece's colours equal those of the whole surface, at the cost of the
 * whole volume's memory per process. When the same output also feeds the
 * surface's branch (reader -> contour), that branch's piece request replaces
 * the whole one (an output holds one request per update): this filter then
 * reports an error instead of casting rays through a piece, unless a
 * subclass assembles the pieces (AssembleVolume; vtkPVVolumeOnSurfaceFilter
 * gathers them over the processes of a distributed run).
 *
 * @sa vtkAdaptiveVolumeMapper vtkOpenMeshDecimation
 */
#ifndef vtkVolumeOnSurfaceFilter_h
#define vtkVolumeOnSurfaceFilter_h

#include "avosRenderingVolumeOnSurfaceModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"
#include "vtkSmartPointer.h" // For vtkSmartPointer
#include "vtkWeakPointer.h"  // For vtkWeakPointer

#include <memory> // For std::unique_ptr

class vtkCamera;
class vtkImageData;
class vtkLightCollection;
class vtkRenderer;
class vtkVolumeProperty;

class AVOSRENDERINGVOLUMEONSURFACE_EXPORT vtkVolumeOnSurfaceFilter : public vtkPolyDataAlgorithm
{
public:
  static vtkVolumeOnSurfaceFilter* New();
  vtkTypeMacro(vtkVolumeOnSurfaceFilter, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /**
   * The volume, on input port 1.
   */
  void SetVolumeConnection(vtkAlgorithmOutput* output);

  ///@{
  /**
   * Colour and opacity of the volume (first component's functions).
   */
  void SetVolumeProperty(vtkVolumeProperty* property);
  vtkGetObjectMacro(VolumeProperty, vtkVolumeProperty);
  ///@}

  ///@{
  /**
   * The camera the colours are assigned for.
   */
  void SetCamera(vtkCamera* camera);
  vtkGetObjectMacro(Camera, vtkCamera);
  ///@}

  ///@{
  /**
   * The renderer whose lights shade the rays when the volume property
   * shades (required then). Not reference counted: the renderer usually
   * draws this filter's output, and a counted reference would make a loop.
   */
  void SetRenderer(vtkRenderer* renderer);
  vtkRenderer* GetRenderer();
  ///@}

  ///@{
  /**
   * Cone opening angles in degrees (half-angles to the normal, in (0, 90]).
   * Default 20, 45, 70.
   */
  void AddOpeningAngle(double degrees);
  void RemoveAllOpeningAngles();
  int GetNumberOfCones();
  double GetOpeningAngle(int cone);
  ///@}

  ///@{
  /**
   * Rays per cone. Default 4; 0 is an error at execution.
   */
  vtkSetMacro(RaysPerCone, int);
  vtkGetMacro(RaysPerCone, int);
  ///@}

  enum VolumeSides
  {
    BEHIND_SURFACE = 0, // cones into the volume behind the surface (the paper's)
    IN_FRONT_OF_SURFACE // cones towards the observer's side
  };

  ///@{
  /**
   * Which volume colours a vertex: BEHIND_SURFACE (default, the paper's
   * VoS^M), the volume behind the surface along the cone ray closest to the
   * observation line; IN_FRONT_OF_SURFACE, the volume on the observer's side.
   */
  vtkSetClampMacro(VolumeSide, int, BEHIND_SURFACE, IN_FRONT_OF_SURFACE);
  vtkGetMacro(VolumeSide, int);
  void SetVolumeSideToBehindSurface() { this->SetVolumeSide(BEHIND_SURFACE); }
  void SetVolumeSideToInFrontOfSurface() { this->SetVolumeSide(IN_FRONT_OF_SURFACE); }
  ///@}

  ///@{
  /**
   * The surface's normals point away from the side its visible vertices are
   * seen from (into the volume): the cones take their opposite. Default off.
   */
  vtkSetMacro(FlipNormals, vtkTypeBool);
  vtkGetMacro(FlipNormals, vtkTypeBool);
  vtkBooleanMacro(FlipNormals, vtkTypeBool);
  ///@}

  enum IntegrationMethods
  {
    LEVOY = 0, // Riemann sum with step SampleDistance (the paper's model)
    ADAPTIVE,  // adaptive Simpson, coupled, to Tolerance
    PIECEWISE  // piecewise adaptive (as vtkAdaptiveVolumeMapper's), to Tolerance on any TF
  };

  ///@{
  /**
   * How each ray is integrated. Default PIECEWISE (the tolerance holds on any
   * transfer function).
   */
  vtkSetClampMacro(IntegrationMethod, int, LEVOY, PIECEWISE);
  vtkGetMacro(IntegrationMethod, int);
  void SetIntegrationMethodToLevoy() { this->SetIntegrationMethod(LEVOY); }
  void SetIntegrationMethodToAdaptive() { this->SetIntegrationMethod(ADAPTIVE); }
  void SetIntegrationMethodToPiecewise() { this->SetIntegrationMethod(PIECEWISE); }
  ///@}

  ///@{
  /**
   * Riemann step (voxel units, default 0.5) and adaptive tolerance (default
   * 0.01); both also bound the early ray termination (eps / 5).
   */
  vtkSetMacro(SampleDistance, double);
  vtkGetMacro(SampleDistance, double);
  vtkSetMacro(Tolerance, double);
  vtkGetMacro(Tolerance, double);
  ///@}

  ///@{
  /**
   * What the scalar opacity function means, as in vtkAdaptiveVolumeMapper:
   * VTK's opacity (default) or the paper's extinction per voxel unit.
   */
  vtkSetMacro(ExtinctionOpacity, vtkTypeBool);
  vtkGetMacro(ExtinctionOpacity, vtkTypeBool);
  vtkBooleanMacro(ExtinctionOpacity, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Integrate each ray only through the 4^3-cell blocks the transfer function
   * leaves visible (default on), as vtkAdaptiveVolumeMapper does: a Riemann
   * sum is unchanged to the bit, the adaptive rule keeps its bound.
   */
  vtkSetMacro(EmptySpaceSkipping, vtkTypeBool);
  vtkGetMacro(EmptySpaceSkipping, vtkTypeBool);
  vtkBooleanMacro(EmptySpaceSkipping, vtkTypeBool);
  ///@}

  /**
   * Rays cast by the last execution: 0 when only the colours were assigned.
   */
  vtkGetMacro(NumberOfRaysCast, vtkIdType);

  ///@{
  /**
   * Memory of the structures of the technique after an execution, in bytes
   * (the paper's Table III): the volume's scalars, the isosurface (points,
   * normals, triangles, colours) and the cones (a direction and an RGBA per
   * ray).
   */
  vtkGetMacro(VolumeMemory, vtkIdType);
  vtkGetMacro(SurfaceMemory, vtkIdType);
  vtkGetMacro(ConesMemory, vtkIdType);
  ///@}

  vtkMTimeType GetMTime() override;

protected:
  vtkVolumeOnSurfaceFilter();
  ~vtkVolumeOnSurfaceFilter() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int RequestUpdateExtent(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  ///@{
  /**
   * The stages of RequestData, in the order data flows: the inputs checked
   * (an error and an empty output for each bad one), the surface's normals
   * (the input's, or computed once per surface), the previsualization (the
   * cone rays of every vertex, cast by CastCones with the ray set-up it
   * prepared, unless nothing they depend on changed, the lights included)
   * and the colour of each vertex for the camera.
   */
  bool ValidateInputs(vtkPolyData* surface, vtkImageData* received, vtkImageData* volume);
  vtkPolyData* UpdateNormals(vtkPolyData* surface);
  bool Previsualize(vtkImageData* volume, vtkPolyData* withNormals);
  bool CastCones(vtkPolyData* withNormals);
  void AssignColours(vtkPolyData* withNormals, vtkPolyData* output);
  ///@}

  /**
   * The lights that shade the rays: the renderer's, or where none is
   * switched on and the renderer creates its own at its first render, that
   * headlight (white, at the camera).
   */
  vtkLightCollection* ShadingLights();

  /**
   * The volume the rays cross, from what input port 1 received (null when
   * nothing) and its information. This filter asks for the whole volume; a
   * part of it means that another consumer of the same output asked for a
   * piece in the same update: here that is an error (null returned, the
   * error reported). Called first in RequestData on every process, before
   * any check, so that an override may communicate with the other processes.
   */
  virtual vtkSmartPointer<vtkImageData> AssembleVolume(
    vtkImageData* received, vtkInformation* volumeInfo);

  /**
   * Whether `received` holds a part only of the whole extent its information
   * gives (stored in `whole`, left as it is when there is none).
   */
  static bool HoldsPart(vtkImageData* received, vtkInformation* volumeInfo, int whole[6]);

  /**
   * The grid `image` samples: its extent, origin, spacing and direction
   * (row by row), in that order. Two volumes with the same grid and the same
   * scalars are the same volume.
   */
  static void GetGrid(vtkImageData* image, double grid[21]);

  vtkVolumeProperty* VolumeProperty = nullptr;
  vtkCamera* Camera = nullptr;
  vtkWeakPointer<vtkRenderer> Renderer;
  int RaysPerCone = 4;
  vtkTypeBool FlipNormals = 0;
  int IntegrationMethod = PIECEWISE;
  int VolumeSide = BEHIND_SURFACE;
  double SampleDistance = 0.5;
  double Tolerance = 0.01;
  vtkTypeBool ExtinctionOpacity = 0;
  vtkTypeBool EmptySpaceSkipping = 1;
  vtkIdType NumberOfRaysCast = 0;
  vtkIdType VolumeMemory = 0;
  vtkIdType SurfaceMemory = 0;
  vtkIdType ConesMemory = 0;

private:
  vtkVolumeOnSurfaceFilter(const vtkVolumeOnSurfaceFilter&) = delete;
  void operator=(const vtkVolumeOnSurfaceFilter&) = delete;

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
