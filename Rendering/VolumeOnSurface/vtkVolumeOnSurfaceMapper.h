/**
 * @class   vtkVolumeOnSurfaceMapper
 * @brief   draws an isosurface coloured by the volume behind it (VoS^M*)
 *
 * The VoS^M* technique of ../shared/papers/volume-on-surface.txt as a
 * polydata mapper: at each render, one ray per visible vertex, starting at
 * the vertex and running along the observation line away from the observer
 * through the volume (input port 1) to its far boundary, integrated front to
 * back with the numerical core (the piecewise method by default, the
 * Riemann sum of the paper's model, or adaptive Simpson); the vertex takes
 * the ray's colour and the lit surface is drawn, opaque, by an OpenGL
 * polydata mapper with the colours' RGB (premultiplied: the volume behind
 * the vertex over black, what a ray cast shows through that point when the
 * surface bounds the empty space in front of the visible volume).
 * VolumeSide IN_FRONT_OF_SURFACE integrates the volume between the vertex
 * and the observer instead. Visible means front-facing (with respect to the point normals, which
 * the surface must have) and inside the view frustum; other vertices cost
 * nothing and stay transparent black, and a polygon with no visible corner
 * is not drawn (nothing would colour it: on a closed surface it is hidden
 * anyway; through an open one, what lies behind shows instead of black).
 * Vertices are processed with vtkSMPTools.
 *
 * Levels of detail: the surface is decimated with vtkOpenMeshDecimation to
 * each of LevelOfDetailReductions (default 0, 0.5, 0.9; built once per
 * surface). With LevelOfDetail -1 (the default) the mapper picks the coarser
 * of two levels: the finest that fits the render window's desired update
 * rate at the time per ray of its last render (coarse while interacting),
 * and the coarsest whose cast vertices are still about PixelsPerVertex
 * covered pixels apart on the screen (a far or small surface needs fewer
 * rays); a level can also be forced. Decimated vertices are a subset of the
 * full surface's (their original ids), so colours already computed for the
 * same view are reused across levels instead of cast again; each level
 * drawn keeps its own OpenGL delegate, so a level drawn again (as the
 * automatic level goes back and forth) does not upload its geometry again.
 *
 * Hidden vertices: with VisibilityTest DEPTH the drawn level is first drawn
 * into the depth buffer only (over the props drawn before it) and read
 * back; a vertex gets a ray only when it is not hidden there, or shares a
 * polygon with one that is not (so every polygon with a visible corner is
 * coloured whole; what stays uncoloured is hidden, but for polygons crossed
 * by an occluding edge with all their corners hidden). That costs one
 * depth-only draw: AUTOMATIC (the default) draws it only when the rays it
 * saved last time, at the current cost per ray, outweigh what it cost (and
 * every 16th new view, to measure again), so a software OpenGL that draws
 * slowly skips it and a GPU keeps it.
 *
 * Shading: with the volume property's Shade on, each ray's emission is lit
 * as vtkAdaptiveVolumeMapper lights it (Blinn-Phong with the exact gradient
 * of the trilinear field, the renderer's switched-on lights: directional,
 * positional, spots; avos/numerics/Shading.h), the piecewise method's error
 * within Tolerance as there. The surface itself is then still lit by the
 * actor's property: turn its lighting off to show the rays' colours alone.
 * Gradient opacity scales the extinction as there too (the piecewise
 * method within Tolerance).
 *
 * Nothing is cast when neither the camera, the viewport, the surface, the
 * volume, the transfer function, the lights (when shading) nor a parameter
 * changed.
 *
 * @sa vtkVolumeOnSurfaceFilter vtkOpenMeshDecimation vtkAdaptiveVolumeMapper
 */
#ifndef vtkVolumeOnSurfaceMapper_h
#define vtkVolumeOnSurfaceMapper_h

#include "avosRenderingVolumeOnSurfaceModule.h" // For export macro
#include "vtkPolyDataMapper.h"

#include <memory> // For std::unique_ptr
#include <string> // For the stages' failure messages
#include <vector> // For SpreadColours

class vtkImageData;
class vtkPolyData;
class vtkVolumeProperty;

class AVOSRENDERINGVOLUMEONSURFACE_EXPORT vtkVolumeOnSurfaceMapper : public vtkPolyDataMapper
{
public:
  static vtkVolumeOnSurfaceMapper* New();
  vtkTypeMacro(vtkVolumeOnSurfaceMapper, vtkPolyDataMapper);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * The volume, on input port 1.
   */
  void SetVolumeConnection(vtkAlgorithmOutput* output);
  void SetVolumeData(vtkImageData* volume);
  ///@}

  ///@{
  /**
   * Colour and opacity of the volume (first component's functions).
   */
  void SetVolumeProperty(vtkVolumeProperty* property);
  vtkGetObjectMacro(VolumeProperty, vtkVolumeProperty);
  ///@}

  enum IntegrationMethods
  {
    LEVOY = 0, // Riemann sum with step SampleDistance
    ADAPTIVE,  // adaptive Simpson, coupled, to Tolerance
    PIECEWISE  // piecewise adaptive (as vtkAdaptiveVolumeMapper's), to Tolerance on any TF
  };

  ///@{
  /**
   * Integration along each ray, as in vtkVolumeOnSurfaceFilter: PIECEWISE
   * (default) or ADAPTIVE with Tolerance (default 0.01), LEVOY with
   * SampleDistance (voxel units, default 0.5); the opacity model (VTK's by
   * default).
   */
  vtkSetClampMacro(IntegrationMethod, int, LEVOY, PIECEWISE);
  vtkGetMacro(IntegrationMethod, int);
  void SetIntegrationMethodToLevoy() { this->SetIntegrationMethod(LEVOY); }
  void SetIntegrationMethodToAdaptive() { this->SetIntegrationMethod(ADAPTIVE); }
  void SetIntegrationMethodToPiecewise() { this->SetIntegrationMethod(PIECEWISE); }
  vtkSetMacro(SampleDistance, double);
  vtkGetMacro(SampleDistance, double);
  vtkSetMacro(Tolerance, double);
  vtkGetMacro(Tolerance, double);
  vtkSetMacro(ExtinctionOpacity, vtkTypeBool);
  vtkGetMacro(ExtinctionOpacity, vtkTypeBool);
  vtkBooleanMacro(ExtinctionOpacity, vtkTypeBool);
  ///@}

  enum VolumeSides
  {
    BEHIND_SURFACE = 0, // from the vertex away from the observer (the paper's)
    IN_FRONT_OF_SURFACE // between the vertex and the observer
  };

  ///@{
  /**
   * Which volume colours a vertex: BEHIND_SURFACE (default, the paper's
   * VoS^M*), the volume from the vertex along the observation line away from
   * the observer to the volume's far boundary; IN_FRONT_OF_SURFACE, the
   * volume between the vertex and the observer (or the volume's boundary on
   * that side).
   */
  vtkSetClampMacro(VolumeSide, int, BEHIND_SURFACE, IN_FRONT_OF_SURFACE);
  vtkGetMacro(VolumeSide, int);
  void SetVolumeSideToBehindSurface() { this->SetVolumeSide(BEHIND_SURFACE); }
  void SetVolumeSideToInFrontOfSurface() { this->SetVolumeSide(IN_FRONT_OF_SURFACE); }
  ///@}

  ///@{
  /**
   * Integrate each ray only through the blocks the transfer function leaves
   * visible (default on), as vtkVolumeOnSurfaceFilter does.
   */
  vtkSetMacro(EmptySpaceSkipping, vtkTypeBool);
  vtkGetMacro(EmptySpaceSkipping, vtkTypeBool);
  vtkBooleanMacro(EmptySpaceSkipping, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Decimation of each level of detail (fractions of triangles removed,
   * finest first). Default 0, 0.5, 0.9.
   */
  void AddLevelOfDetailReduction(double reduction);
  void RemoveAllLevelOfDetailReductions();
  int GetNumberOfLevelsOfDetail();
  ///@}

  ///@{
  /**
   * The level drawn: -1 (default) picks it from the desired update rate.
   * GetLastLevelOfDetail() tells which was drawn last.
   */
  vtkSetMacro(LevelOfDetail, int);
  vtkGetMacro(LevelOfDetail, int);
  vtkGetMacro(LastLevelOfDetail, int);
  ///@}

  ///@{
  /**
   * The automatic level's screen density: the coarsest level whose cast
   * vertices (front-facing, in the frustum) have at most this many covered
   * pixels each is enough; finer ones cast more rays than the screen shows.
   * Default 2 (one ray per one to two pixels); 0 turns the density rule off.
   */
  vtkSetClampMacro(PixelsPerVertex, double, 0.0, 1.0e6);
  vtkGetMacro(PixelsPerVertex, double);
  ///@}

  ///@{
  /**
   * Draw the full surface whatever the level of detail (default off): the
   * rays are cast at the chosen level's vertices (a subset of the full
   * surface's, see above) and every other vertex of the full surface takes
   * a convex combination of the colours of the level's vertices nearest to
   * it along the surface's edges (weighted by inverse distance); a vertex
   * none of whose nearest level vertices got a ray (beside a silhouette)
   * gets its own. The decimated levels then save rays but not the full
   * surface's geometry and shading: for an OpenGL that draws fast (a GPU),
   * where the rays make the frame. GetLastLevelOfDetail() tells the level
   * cast, GetColoredSurface() the full surface drawn.
   */
  vtkSetMacro(DrawFullSurface, vtkTypeBool);
  vtkGetMacro(DrawFullSurface, vtkTypeBool);
  vtkBooleanMacro(DrawFullSurface, vtkTypeBool);
  ///@}

  enum VisibilityTests
  {
    NO_VISIBILITY = 0,    // every front-facing vertex in the frustum gets a ray
    DEPTH_VISIBILITY,     // a depth-only pass first: hidden vertices get none
    AUTOMATIC_VISIBILITY, // the depth pass when it saved more than it cost
  };

  ///@{
  /**
   * Which vertices get a ray (see the class description). Default
   * AUTOMATIC_VISIBILITY.
   */
  vtkSetClampMacro(VisibilityTest, int, NO_VISIBILITY, AUTOMATIC_VISIBILITY);
  vtkGetMacro(VisibilityTest, int);
  ///@}

  ///@{
  /**
   * The last render that cast: whether it drew the depth pass, and the
   * front-facing vertices in the frustum it found hidden (no ray).
   */
  vtkGetMacro(LastDepthPass, vtkTypeBool);
  vtkGetMacro(NumberOfHiddenVertices, vtkIdType);
  ///@}

  /**
   * The full surface's covered pixels per cast vertex that the last
   * automatic choice of level saw (-1 when the level was forced).
   */
  double GetScreenPixelsPerVertex();

  ///@{
  /**
   * The last render: rays cast (0 when nothing changed), visible vertices,
   * colours reused from another level, seconds spent colouring.
   */
  vtkGetMacro(NumberOfRaysCast, vtkIdType);
  vtkGetMacro(NumberOfVisibleVertices, vtkIdType);
  vtkGetMacro(NumberOfReusedColors, vtkIdType);
  vtkGetMacro(ColoringTime, double);
  ///@}

  ///@{
  /**
   * Memory of the technique's structures, in bytes (the paper's Tables III
   * and IV): the volume's scalars, and the surface of one level of detail
   * (points, normals, triangles and per vertex its RGBA colour and the RGB
   * drawn). 0 before the first render built the levels, or for a level that
   * does not exist.
   */
  vtkIdType GetVolumeMemory();
  vtkIdType GetSurfaceMemory(int level);
  ///@}

  /**
   * The surface the last render coloured, the chosen level of detail (the
   * full surface with DrawFullSurface; all its polygons, drawn or not),
   * with its "VoSColors" (unsigned char RGBA, the active scalars),
   * their RGB "VoSDisplayColors" (what is drawn) and, for decimated levels,
   * "vtkOriginalPointIds".
   */
  vtkPolyData* GetColoredSurface();

  void Render(vtkRenderer* ren, vtkActor* act) override;
  void ReleaseGraphicsResources(vtkWindow* win) override;

protected:
  vtkVolumeOnSurfaceMapper();
  ~vtkVolumeOnSurfaceMapper() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;

  ///@{
  /**
   * The stages of Render, in the order data flows: the inputs checked, the
   * levels of detail (once per surface), the view and its key (true: a new
   * view, whose colours start again in StartView), the level drawn, and,
   * when that level has no colours for this view yet, ColourLevel: the ray
   * set-up, the drawing (SelectDrawing), the depth pass (TestVisibility),
   * the rays of the vertices that want one (CastLevelRays, SpreadColours for
   * the full surface's others) and the colours stored (StoreColours).
   */
  bool ValidateInputs();
  bool UpdateLevels(vtkRenderer* ren);
  bool UpdateView(vtkRenderer* ren);
  int ChooseLevel(vtkRenderer* ren, bool newView);
  void StartView();
  bool ColourLevel(vtkRenderer* ren, vtkActor* act, int level);
  void SelectDrawing(int level);
  void TestVisibility(vtkRenderer* ren, vtkActor* act);
  void CastLevelRays(int level, std::string& failure);
  std::vector<vtkIdType> SpreadColours(int level);
  void StoreColours(int level);
  ///@}

  vtkVolumeProperty* VolumeProperty = nullptr;
  int IntegrationMethod = PIECEWISE;
  int VolumeSide = BEHIND_SURFACE;
  double SampleDistance = 0.5;
  double Tolerance = 0.01;
  vtkTypeBool ExtinctionOpacity = 0;
  vtkTypeBool EmptySpaceSkipping = 1;
  int LevelOfDetail = -1;
  int LastLevelOfDetail = -1;
  double PixelsPerVertex = 2.0;
  int VisibilityTest = AUTOMATIC_VISIBILITY;
  vtkTypeBool DrawFullSurface = 0;
  vtkTypeBool LastDepthPass = 0;
  vtkIdType NumberOfHiddenVertices = 0;
  vtkIdType NumberOfRaysCast = 0;
  vtkIdType NumberOfVisibleVertices = 0;
  vtkIdType NumberOfReusedColors = 0;
  double ColoringTime = 0.0;

private:
  vtkVolumeOnSurfaceMapper(const vtkVolumeOnSurfaceMapper&) = delete;
  void operator=(const vtkVolumeOnSurfaceMapper&) = delete;

  class vtkInternals;
  std::unique_ptr<vtkInternals> Internals;
};

#endif
