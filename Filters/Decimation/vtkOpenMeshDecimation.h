/**
 * @class   vtkOpenMeshDecimation
 * @brief   topology-preserving decimation of triangle meshes by halfedge collapses
 *
 * vtkOpenMeshDecimation reduces a triangle mesh with OpenMesh's decimaters:
 * halfedge collapses ordered by the quadric error (Garland and Heckbert),
 * each one allowed only if it keeps the mesh manifold (the link condition: no
 * holes, no change of genus) and passes the enabled constraints (bounded
 * normal deviation, Hausdorff tolerance, maximum aspect ratio). A halfedge
 * collapse removes one vertex and leaves the other where it was, so the
 * output vertices are a subset of the input's, at their exact positions:
 * all point data is carried across unchanged, and the array
 * "vtkOriginalPointIds" records each output vertex's input id, so per-vertex
 * results computed on the full surface apply to the decimated one as they
 * are.
 *
 * The amount of decimation is a TargetReduction (the fraction of triangles
 * to remove, like vtkDecimatePro's) or a TargetNumberOfVertices. Boundary
 * vertices are kept unless BoundaryVertexDeletion is on, so boundaries keep
 * their shape; a collapse that would change a boundary's topology is never
 * taken. The reduction may stop short of the target when no collapse passes
 * the constraints; GetAchievedReduction() says how far it got.
 *
 * Input: polygons and triangle strips (triangulated first when they are not
 * triangles); vertices and lines are ignored with a warning. Faces that
 * cannot join a manifold mesh (a third face on an edge, a pinched vertex)
 * keep their own copies of their vertices and are reported with a warning;
 * degenerate triangles are dropped and reported.
 *
 * Distributed input: ghost cells (vtkGhostType with DUPLICATECELL, another
 * piece's cells) are left out, so each piece decimates only the triangles it
 * owns and no triangle is output twice; the vertices a piece shares with
 * ghost cells (its border with the neighbouring pieces) are locked, even
 * with BoundaryVertexDeletion on, so that the pieces keep meeting along the
 * same edges. The output has no ghost cells. An empty piece, or one of
 * ghost cells only, gives an empty output (an error only when the whole
 * input is empty).
 *
 * @sa vtkDecimatePro vtkQuadricDecimation
 */
#ifndef vtkOpenMeshDecimation_h
#define vtkOpenMeshDecimation_h

#include "avosFiltersDecimationModule.h" // For export macro
#include "vtkPolyDataAlgorithm.h"

class AVOSFILTERSDECIMATION_EXPORT vtkOpenMeshDecimation : public vtkPolyDataAlgorithm
{
public:
  static vtkOpenMeshDecimation* New();
  vtkTypeMacro(vtkOpenMeshDecimation, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /**
   * Fraction of the triangles to remove, in [0, 1). Default 0.5. Used when
   * TargetNumberOfVertices is 0.
   */
  vtkSetClampMacro(TargetReduction, double, 0.0, 1.0);
  vtkGetMacro(TargetReduction, double);
  ///@}

  ///@{
  /**
   * Number of vertices to keep instead of a reduction; 0 (the default) uses
   * TargetReduction.
   */
  vtkSetClampMacro(TargetNumberOfVertices, vtkIdType, 0, VTK_ID_MAX);
  vtkGetMacro(TargetNumberOfVertices, vtkIdType);
  ///@}

  enum DecimaterTypes
  {
    EXACT = 0,       // always the collapse of least quadric error (a priority queue)
    MULTIPLE_CHOICE, // the best of a few random candidates per step: faster, coarser
    MIXED,           // multiple choice for most of the way, exact for the last 20 %
    LAZY // least error first, legality and constraints checked only for the next candidate
  };

  ///@{
  /**
   * Which decimater runs. Default LAZY: like EXACT (OpenMesh's DecimaterT)
   * always the legal collapse of least quadric error, but 3 to 6 times faster
   * on million-triangle meshes, and with Garland and Heckbert's unweighted
   * plane quadrics, which halved the Hausdorff distance in our measurements.
   */
  vtkSetClampMacro(DecimaterType, int, EXACT, LAZY);
  vtkGetMacro(DecimaterType, int);
  void SetDecimaterTypeToExact() { this->SetDecimaterType(EXACT); }
  void SetDecimaterTypeToMultipleChoice() { this->SetDecimaterType(MULTIPLE_CHOICE); }
  void SetDecimaterTypeToMixed() { this->SetDecimaterType(MIXED); }
  void SetDecimaterTypeToLazy() { this->SetDecimaterType(LAZY); }
  ///@}

  ///@{
  /**
   * Largest angle, in degrees, by which a collapse may turn the normal of a
   * face around it. Default 45: besides preventing flips, it keeps thin
   * features (measured on a 1.1 M-triangle isosurface at 75 %: Hausdorff
   * distance 0.039 % of the diagonal at 45, 0.163 % at 90). 180 disables
   * the check.
   */
  vtkSetClampMacro(MaximumNormalDeviation, double, 0.0, 180.0);
  vtkGetMacro(MaximumNormalDeviation, double);
  ///@}

  ///@{
  /**
   * Largest distance, in world units, between a removed vertex and the
   * decimated surface; 0 (the default) disables the constraint.
   */
  vtkSetClampMacro(HausdorffTolerance, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(HausdorffTolerance, double);
  ///@}

  ///@{
  /**
   * LAZY only, when HausdorffTolerance is 0: bound the distance of the
   * vertices removed by the last collapses, from half the input's triangles
   * (or four times the target's, if later) on, where the largest errors
   * arise. The bound starts at twice the square root of the last quadric
   * error taken and doubles whenever no collapse passes it, so the target is
   * still reached (or the same topological limit), with a smaller maximum
   * distance: on a 1.1 M-triangle isosurface at 90 %, 0.051 % of the
   * diagonal instead of 0.068 %, at the same speed (see
   * docs/decimation-benchmark.md). Default on; no effect up to 50 %.
   */
  vtkSetMacro(AdaptiveHausdorff, vtkTypeBool);
  vtkGetMacro(AdaptiveHausdorff, vtkTypeBool);
  vtkBooleanMacro(AdaptiveHausdorff, vtkTypeBool);
  ///@}

  ///@{
  /**
   * Largest aspect ratio (a triangle's longest edge over its height: 1.155
   * for an equilateral triangle) a collapse may create, unless it improves on
   * the worst triangle around it; 0 (the default) disables the constraint.
   */
  vtkSetClampMacro(MaximumAspectRatio, double, 0.0, VTK_DOUBLE_MAX);
  vtkGetMacro(MaximumAspectRatio, double);
  ///@}

  ///@{
  /**
   * Allow boundary vertices to be removed (along their boundary). Default
   * off: boundaries are kept exactly.
   */
  vtkSetMacro(BoundaryVertexDeletion, vtkTypeBool);
  vtkGetMacro(BoundaryVertexDeletion, vtkTypeBool);
  vtkBooleanMacro(BoundaryVertexDeletion, vtkTypeBool);
  ///@}

  /**
   * Fraction of the input triangles removed by the last update.
   */
  vtkGetMacro(AchievedReduction, double);

  /**
   * The adaptive Hausdorff bound the last update ended with (world units),
   * 0 when it did not apply.
   */
  vtkGetMacro(HausdorffBound, double);

protected:
  vtkOpenMeshDecimation() = default;
  ~vtkOpenMeshDecimation() override = default;

  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

  double TargetReduction = 0.5;
  vtkIdType TargetNumberOfVertices = 0;
  int DecimaterType = LAZY;
  double MaximumNormalDeviation = 45.0;
  double HausdorffTolerance = 0.0;
  vtkTypeBool AdaptiveHausdorff = 1;
  double MaximumAspectRatio = 0.0;
  vtkTypeBool BoundaryVertexDeletion = 0;
  double AchievedReduction = 0.0;
  double HausdorffBound = 0.0;

private:
  vtkOpenMeshDecimation(const vtkOpenMeshDecimation&) = delete;
  void operator=(const vtkOpenMeshDecimation&) = delete;
};

#endif
