#include "vtkOpenMeshDecimation.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMath.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkTriangleFilter.h"

#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Core/System/omstream.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/McDecimaterT.hh>
#include <OpenMesh/Tools/Decimater/MixedDecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModAspectRatioT.hh>
#include <OpenMesh/Tools/Decimater/ModHausdorffT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>
#include <OpenMesh/Tools/Decimater/Observer.hh>

#include <algorithm>
#include <cmath>
#include <vector>

namespace
{
// Double-precision points: input coordinates survive the round trip exactly.
// Status attributes are part of the mesh type, so they outlive the decimater
// (it releases the ones it requested itself, and garbage_collection() needs
// them).
struct MeshTraits : public OpenMesh::DefaultTraits
{
  using Point = OpenMesh::Vec3d;
  using Normal = OpenMesh::Vec3d;
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status | OpenMesh::Attributes::Normal);
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

// Reports the decimater's steps as the filter's progress (10 % to 90 %) and
// stops it when the filter is aborted.
class DecimationProgress : public OpenMesh::Decimater::Observer
{
public:
  DecimationProgress(vtkOpenMeshDecimation* filter, std::size_t steps)
    : Observer(std::max<std::size_t>(steps / 50, 1))
    , Filter(filter)
    , Steps(std::max<std::size_t>(steps, 1))
  {
  }
  void notify(std::size_t step) override
  {
    this->Filter->UpdateProgress(0.1 + 0.8 * std::min(1.0, double(step) / double(this->Steps)));
  }
  bool abort() const override { return this->Filter->GetAbortExecute() != 0; }

private:
  vtkOpenMeshDecimation* Filter;
  std::size_t Steps;
};

struct Constraints
{
  double NormalDeviation;
  double Hausdorff;
  double AspectRatio;
};

// One priority (the quadric error), the rest binary constraints.
template <typename Decimater>
void AddModules(Decimater& decimater, const Constraints& c)
{
  typename OpenMesh::Decimater::ModQuadricT<Mesh>::Handle quadric;
  decimater.add(quadric);
  decimater.module(quadric).unset_max_err();
  if (c.NormalDeviation < 180.0)
  {
    typename OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle normals;
    decimater.add(normals);
    decimater.module(normals).set_max_normal_deviation(c.NormalDeviation); // always binary
  }
  if (c.Hausdorff > 0.0)
  {
    typename OpenMesh::Decimater::ModHausdorffT<Mesh>::Handle hausdorff;
    decimater.add(hausdorff);
    decimater.module(hausdorff).set_tolerance(c.Hausdorff);
    decimater.module(hausdorff).set_binary(true);
  }
  if (c.AspectRatio > 0.0)
  {
    typename OpenMesh::Decimater::ModAspectRatioT<Mesh>::Handle aspect;
    decimater.add(aspect);
    decimater.module(aspect).set_aspect_ratio(static_cast<float>(c.AspectRatio));
    decimater.module(aspect).set_binary(true);
  }
}

// Runs one kind of decimater down to `faces` faces (or `vertices` vertices
// when non-zero). False when the modules could not be initialised.
template <typename Decimater, typename... Extra>
bool Decimate(Mesh& mesh, const Constraints& c, DecimationProgress& observer, std::size_t vertices,
  std::size_t faces, Extra... extra)
{
  Decimater decimater(mesh);
  AddModules(decimater, c);
  decimater.set_observer(&observer);
  if (!decimater.initialize())
  {
    return false;
  }
  decimater.decimate_to_faces(vertices, vertices > 0 ? 0 : faces, extra...);
  return true;
}
} // namespace

vtkStandardNewMacro(vtkOpenMeshDecimation);

int vtkOpenMeshDecimation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->AchievedReduction = 0.0;
  if (!input || input->GetNumberOfPolys() + input->GetNumberOfStrips() == 0)
  {
    vtkErrorMacro(<< "The input has no polygons to decimate.");
    return 1;
  }
  if (input->GetNumberOfVerts() + input->GetNumberOfLines() > 0)
  {
    vtkWarningMacro(<< "Vertices and lines of the input are ignored.");
  }
  for (vtkIdType i = 0; i < input->GetNumberOfPoints(); ++i)
  {
    double p[3];
    input->GetPoint(i, p);
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
    {
      vtkErrorMacro(<< "Point " << i << " is not finite: the input cannot be decimated.");
      return 1;
    }
  }

  // Triangles only: polygons and strips are triangulated (ids unchanged).
  vtkSmartPointer<vtkPolyData> triangles = input;
  bool allTriangles = input->GetNumberOfStrips() == 0;
  {
    auto it = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
    for (it->GoToFirstCell(); allTriangles && !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      allTriangles = it->GetCurrentCell()->GetNumberOfIds() == 3;
    }
  }
  if (!allTriangles)
  {
    vtkNew<vtkPolyData> polygons;
    polygons->SetPoints(input->GetPoints());
    polygons->SetPolys(input->GetPolys());
    polygons->SetStrips(input->GetStrips());
    vtkNew<vtkTriangleFilter> triangulate;
    triangulate->SetInputData(polygons);
    triangulate->PassVertsOff();
    triangulate->PassLinesOff();
    triangulate->Update();
    triangles = triangulate->GetOutput();
  }

  // The OpenMesh mesh. A face that cannot join the manifold mesh gets its own
  // copies of its vertices; degenerate triangles are dropped.
  Mesh mesh;
  OpenMesh::VPropHandleT<vtkIdType> originalId;
  mesh.add_property(originalId);
  const vtkIdType numberOfPoints = input->GetNumberOfPoints();
  std::vector<Mesh::VertexHandle> handles(static_cast<std::size_t>(numberOfPoints));
  auto addVertex = [&](vtkIdType id)
  {
    double p[3];
    input->GetPoint(id, p);
    const Mesh::VertexHandle v = mesh.add_vertex(Mesh::Point(p[0], p[1], p[2]));
    mesh.property(originalId, v) = id;
    return v;
  };
  vtkIdType degenerate = 0, nonManifold = 0;
  const bool errorsWereOn = omerr().is_enabled();
  omerr().disable(); // add_face reports complex edges itself; we count them
  {
    auto it = vtk::TakeSmartPointer(triangles->GetPolys()->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
    {
      vtkIdList* ids = it->GetCurrentCell();
      const vtkIdType a = ids->GetId(0), b = ids->GetId(1), c = ids->GetId(2);
      if (a == b || b == c || a == c || a < 0 || b < 0 || c < 0 || a >= numberOfPoints ||
        b >= numberOfPoints || c >= numberOfPoints)
      {
        ++degenerate;
        continue;
      }
      Mesh::VertexHandle v[3];
      const vtkIdType corner[3] = { a, b, c };
      for (int k = 0; k < 3; ++k)
      {
        Mesh::VertexHandle& h = handles[static_cast<std::size_t>(corner[k])];
        if (!h.is_valid())
        {
          h = addVertex(corner[k]);
        }
        v[k] = h;
      }
      if (!mesh.add_face(v[0], v[1], v[2]).is_valid())
      {
        ++nonManifold;
        mesh.add_face(addVertex(a), addVertex(b), addVertex(c));
      }
    }
  }
  if (errorsWereOn)
  {
    omerr().enable();
  }
  if (degenerate > 0)
  {
    vtkWarningMacro(<< degenerate << " degenerate triangle(s) were dropped.");
  }
  if (nonManifold > 0)
  {
    vtkWarningMacro(<< nonManifold
                    << " triangle(s) could not join a manifold mesh (a third face on an edge "
                       "or a pinched vertex) and keep their own copies of their vertices.");
  }
  const std::size_t facesIn = mesh.n_faces();
  if (facesIn == 0)
  {
    vtkErrorMacro(<< "The input has no usable triangles.");
    return 1;
  }
  if (!this->BoundaryVertexDeletion)
  {
    for (const Mesh::VertexHandle v : mesh.vertices())
    {
      if (mesh.is_boundary(v))
      {
        mesh.status(v).set_locked(true);
      }
    }
  }
  mesh.update_face_normals();
  this->UpdateProgress(0.1);

  // Decimate.
  const std::size_t targetVertices = static_cast<std::size_t>(this->TargetNumberOfVertices);
  const std::size_t targetFaces = static_cast<std::size_t>(
    std::llround(static_cast<double>(facesIn) * (1.0 - this->TargetReduction)));
  const std::size_t steps = targetVertices > 0
    ? (mesh.n_vertices() > targetVertices ? mesh.n_vertices() - targetVertices : 0)
    : (facesIn - std::min(facesIn, targetFaces)) / 2; // a collapse removes two faces
  DecimationProgress observer(this, steps);
  const Constraints constraints{ this->MaximumNormalDeviation, this->HausdorffTolerance,
    this->MaximumAspectRatio };
  bool initialised = true;
  switch (this->DecimaterType)
  {
    case MULTIPLE_CHOICE:
      initialised = Decimate<OpenMesh::Decimater::McDecimaterT<Mesh>>(
        mesh, constraints, observer, targetVertices, targetFaces);
      break;
    case MIXED:
      initialised = Decimate<OpenMesh::Decimater::MixedDecimaterT<Mesh>>(
        mesh, constraints, observer, targetVertices, targetFaces, 0.8f);
      break;
    default:
      initialised = Decimate<OpenMesh::Decimater::DecimaterT<Mesh>>(
        mesh, constraints, observer, targetVertices, targetFaces);
  }
  if (!initialised)
  {
    vtkErrorMacro(<< "OpenMesh's decimater could not be initialised.");
    return 1;
  }
  mesh.garbage_collection();

  // The output: surviving vertices at their input positions, with their point
  // data and original ids, and the remaining triangles.
  const vtkIdType numberOfVertices = static_cast<vtkIdType>(mesh.n_vertices());
  vtkNew<vtkPoints> points;
  points->SetDataType(input->GetPoints()->GetDataType());
  points->SetNumberOfPoints(numberOfVertices);
  vtkNew<vtkIdTypeArray> ids;
  ids->SetName("vtkOriginalPointIds");
  ids->SetNumberOfTuples(numberOfVertices);
  vtkPointData* inPD = input->GetPointData();
  vtkPointData* outPD = output->GetPointData();
  outPD->CopyAllocate(inPD, numberOfVertices);
  for (const Mesh::VertexHandle v : mesh.vertices())
  {
    const vtkIdType out = v.idx();
    const vtkIdType in = mesh.property(originalId, v);
    const Mesh::Point& p = mesh.point(v);
    points->SetPoint(out, p[0], p[1], p[2]);
    ids->SetValue(out, in);
    outPD->CopyData(inPD, in, out);
  }
  outPD->AddArray(ids);
  vtkNew<vtkCellArray> polys;
  polys->AllocateExact(static_cast<vtkIdType>(mesh.n_faces()), 3 * mesh.n_faces());
  for (const Mesh::FaceHandle f : mesh.faces())
  {
    vtkIdType triangle[3];
    int k = 0;
    for (const Mesh::VertexHandle v : mesh.fv_range(f))
    {
      triangle[k++] = v.idx();
    }
    polys->InsertNextCell(3, triangle);
  }
  output->SetPoints(points);
  output->SetPolys(polys);
  this->AchievedReduction = 1.0 - static_cast<double>(mesh.n_faces()) / static_cast<double>(facesIn);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkOpenMeshDecimation::PrintSelf(ostream& os, vtkIndent indent)
{
  static const char* types[] = { "Exact", "MultipleChoice", "Mixed" };
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetReduction: " << this->TargetReduction << "\n";
  os << indent << "TargetNumberOfVertices: " << this->TargetNumberOfVertices << "\n";
  os << indent << "DecimaterType: " << types[this->DecimaterType] << "\n";
  os << indent << "MaximumNormalDeviation: " << this->MaximumNormalDeviation << "\n";
  os << indent << "HausdorffTolerance: " << this->HausdorffTolerance << "\n";
  os << indent << "MaximumAspectRatio: " << this->MaximumAspectRatio << "\n";
  os << indent << "BoundaryVertexDeletion: " << this->BoundaryVertexDeletion << "\n";
  os << indent << "AchievedReduction: " << this->AchievedReduction << "\n";
}
