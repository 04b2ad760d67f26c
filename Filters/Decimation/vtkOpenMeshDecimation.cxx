#include "vtkOpenMeshDecimation.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkDataSetAttributes.h"
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
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkTriangleFilter.h"
#include "vtkUnsignedCharArray.h"

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

#include <OpenMesh/Core/Geometry/QuadricT.hh>

#include <algorithm>
#include <cmath>
#include <functional>
#include <memory>
#include <queue>
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

template <typename ModuleT>
struct ModuleTag
{
  using Type = ModuleT;
};

// The binary constraints, whichever decimater holds them: `add` takes a
// ModuleTag, creates a module of that type and returns it.
template <typename Add>
void AddConstraints(const Constraints& c, Add&& add)
{
  if (c.NormalDeviation < 180.0)
  {
    // Always binary.
    add(ModuleTag<OpenMesh::Decimater::ModNormalFlippingT<Mesh>>())
      .set_max_normal_deviation(c.NormalDeviation);
  }
  if (c.Hausdorff > 0.0)
  {
    auto& hausdorff = add(ModuleTag<OpenMesh::Decimater::ModHausdorffT<Mesh>>());
    hausdorff.set_tolerance(c.Hausdorff);
    hausdorff.set_binary(true);
  }
  if (c.AspectRatio > 0.0)
  {
    auto& aspect = add(ModuleTag<OpenMesh::Decimater::ModAspectRatioT<Mesh>>());
    aspect.set_aspect_ratio(static_cast<float>(c.AspectRatio));
    aspect.set_binary(true);
  }
}

// One priority (the quadric error), the rest binary constraints.
template <typename Decimater>
void AddModules(Decimater& decimater, const Constraints& c)
{
  typename OpenMesh::Decimater::ModQuadricT<Mesh>::Handle quadric;
  decimater.add(quadric);
  decimater.module(quadric).unset_max_err();
  AddConstraints(
    c, [&decimater](auto tag) -> auto& {
      typename decltype(tag)::Type::Handle handle;
      decimater.add(handle);
      return decimater.module(handle);
    });
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

// The least-quadric-error order with lazy evaluation. OpenMesh's DecimaterT
// re-evaluates every candidate collapse of every vertex around a collapse
// (legality and all constraints, about 36 per collapse). Here the priority
// queue holds edges keyed by the quadric error of their cheaper direction
// (the other direction is queued only if that one is illegal), and legality
// and constraints are checked when a candidate reaches the top: the collapse
// taken is still the legal one of least error. A collapse into v changes the
// error of the halfedges at v only: they get new entries, and the old ones
// turn stale (each vertex has a stamp, renewed when v is). A candidate found
// illegal is parked; it can become legal only when the one-ring of one of
// its ends changes, so the parked halfedges at v's neighbours are queued
// again after each collapse.
class LazyDecimater
{
public:
  LazyDecimater(Mesh& mesh, const Constraints& c)
    : M(mesh)
    , Quadrics(mesh.n_vertices())
    , Stamps(mesh.n_vertices(), 0)
    , Parked(mesh.n_halfedges(), 0)
  {
    AddConstraints(
      c, [ this, &mesh ](auto tag) -> auto& {
        auto* module = new typename decltype(tag)::Type(mesh);
        this->Modules.emplace_back(module);
        return *module;
      });
    for (auto& module : this->Modules)
    {
      module->initialize();
    }
    // Plane quadrics, unweighted as in Garland and Heckbert's paper. (OpenMesh's
    // ModQuadricT weights them by area; measured on a 1.1 M-triangle
    // isosurface, unweighted ones halve the Hausdorff distance at 25 to 90 %.)
    for (const Mesh::FaceHandle f : mesh.faces())
    {
      Mesh::Point p[3];
      int k = 0;
      for (const Mesh::VertexHandle v : mesh.fv_range(f))
      {
        p[k++] = mesh.point(v);
      }
      Mesh::Point n = OpenMesh::cross(p[1] - p[0], p[2] - p[0]);
      const double twiceArea = n.norm();
      if (twiceArea > 0.0)
      {
        n /= twiceArea;
      }
      OpenMesh::Geometry::Quadricd q(n[0], n[1], n[2], -OpenMesh::dot(n, p[0]));
      for (const Mesh::VertexHandle v : mesh.fv_range(f))
      {
        this->Quadrics[v.idx()] += q;
      }
    }
    // All halfedges at once: heapifying is linear, pushing one by one is not.
    std::vector<Candidate> all;
    all.reserve(mesh.n_edges());
    for (const Mesh::EdgeHandle e : mesh.edges())
    {
      this->PushEdge(mesh.halfedge_handle(e, 0), &all);
    }
    this->Queue = std::priority_queue<Candidate>(std::less<Candidate>(), std::move(all));
  }

  // Collapses until at most `faces` faces (or `vertices` vertices when
  // non-zero) remain or no legal collapse is left. From `boundFrom` faces on
  // (0: never), the adaptive Hausdorff bound applies; `diagonal` is the
  // mesh's bounding-box diagonal.
  void Decimate(std::size_t vertices, std::size_t faces, std::size_t boundFrom, double diagonal,
    DecimationProgress& progress)
  {
    std::size_t n = 0;
    std::size_t nv = this->M.n_vertices(), nf = this->M.n_faces();
    const std::size_t interval = progress.get_interval();
    while (vertices > 0 ? nv > vertices : nf > faces)
    {
      if (!this->Bound && nf <= boundFrom)
      {
        this->StartBound(diagonal);
      }
      if (this->Queue.empty())
      {
        if (this->Relax())
        {
          continue;
        }
        break;
      }
      const Candidate c = this->Queue.top();
      this->Queue.pop();
      const Mesh::HalfedgeHandle h(c.Halfedge);
      if (this->M.status(this->M.edge_handle(h)).deleted())
      {
        continue;
      }
      const Mesh::VertexHandle v0 = this->M.from_vertex_handle(h);
      const Mesh::VertexHandle v1 = this->M.to_vertex_handle(h);
      if (this->Stamps[v0.idx()] != c.Stamp0 || this->Stamps[v1.idx()] != c.Stamp1)
      {
        continue; // stale
      }
      CollapseInfo ci(this->M, h);
      const bool legal = this->Legal(ci);
      const bool bounded = legal && this->Bound && this->Bound->collapse_priority(ci) < 0.0f;
      if (!legal || bounded)
      {
        if (bounded)
        {
          this->BoundParked.push_back(h.idx());
        }
        // The edge's other direction, at its own error, if not tried yet.
        this->Parked[h.idx()] = 1;
        const Mesh::HalfedgeHandle o = this->M.opposite_halfedge_handle(h);
        if (!c.Single && !this->Parked[o.idx()])
        {
          this->Push(o, true);
        }
        continue;
      }
      for (auto& module : this->Modules)
      {
        module->preprocess_collapse(ci);
      }
      this->LastError = c.Error;
      const bool boundary = this->M.is_boundary(this->M.edge_handle(h));
      this->M.collapse(h);
      nv -= 1;
      nf -= boundary ? 1 : 2;
      this->Quadrics[v1.idx()] += this->Quadrics[v0.idx()];
      for (const Mesh::FaceHandle f : this->M.vf_range(v1))
      {
        this->M.set_normal(f, this->M.calc_face_normal(f));
      }
      for (auto& module : this->Modules)
      {
        module->postprocess_collapse(ci);
      }
      if (this->Bound)
      {
        this->Bound->postprocess_collapse(ci);
      }
      this->Touch(v1);
      if (++n % interval == 0)
      {
        progress.notify(n);
        if (progress.abort())
        {
          return;
        }
      }
    }
  }

  // The adaptive bound reached (0 when it never applied).
  double GetBound() const { return this->Bound ? this->Bound->tolerance() : 0.0; }

private:
  using CollapseInfo = OpenMesh::Decimater::CollapseInfoT<Mesh>;
  using Hausdorff = OpenMesh::Decimater::ModHausdorffT<Mesh>;

  // The adaptive Hausdorff bound: from now on, the vertices a collapse
  // removes are kept with the face nearest to them, and a collapse must
  // leave each within the bound of the surface. The bound starts at twice
  // the scale of the last quadric error taken (the square root of a sum of
  // squared plane distances) and doubles whenever no collapse passes it
  // (Relax). Starting at once the scale was slower (1.6x on the 1.1 M-
  // triangle analytic isosurface at 90 %: many candidates parked and
  // checked again) and no closer (0.053 % of the diagonal against 0.051 %).
  void StartBound(double diagonal)
  {
    this->Bound = std::make_unique<Hausdorff>(this->M);
    this->Bound->initialize();
    this->Bound->set_tolerance(
      std::max(2 * std::sqrt(std::max(double(this->LastError), 0.0)), 1e-6 * diagonal));
  }

  // No candidate is left: doubles the bound and queues again the halfedges
  // the bound has parked since the last call (those parked as illegal wait
  // for their neighbourhood to change, as before). False when the bound
  // parked none: then it is not what stops the decimation (the target may
  // be out of topological reach). Each call doubles the bound and no point
  // is farther than the diagonal from any face, so there are at most
  // log2(diagonal / initial bound) + 2 calls.
  bool Relax()
  {
    if (!this->Bound || this->BoundParked.empty())
    {
      return false;
    }
    this->Bound->set_tolerance(2.0 * this->Bound->tolerance());
    for (const int i : this->BoundParked)
    {
      const Mesh::HalfedgeHandle h(i);
      if (this->Parked[i] && !this->M.status(this->M.edge_handle(h)).deleted())
      {
        this->Parked[i] = 0;
        this->Push(h, true);
      }
    }
    this->BoundParked.clear();
    return true;
  }

  // 16 bytes: the queue is the decimater's main memory traffic. A float
  // error orders collapses as the double would, up to ties within 1e-7.
  struct Candidate
  {
    float Error;
    int Halfedge : 31;
    unsigned Single : 1;
    unsigned Stamp0;
    unsigned Stamp1;
    bool operator<(const Candidate& other) const { return this->Error > other.Error; }
  };

  // The error of moving v0 onto v1: (Q0 + Q1)(p1).
  Candidate Evaluate(Mesh::HalfedgeHandle h) const
  {
    const Mesh::VertexHandle v0 = this->M.from_vertex_handle(h);
    const Mesh::VertexHandle v1 = this->M.to_vertex_handle(h);
    OpenMesh::Geometry::Quadricd q = this->Quadrics[v0.idx()];
    q += this->Quadrics[v1.idx()];
    Candidate c;
    c.Error = static_cast<float>(q(this->M.point(v1)));
    c.Halfedge = h.idx();
    c.Single = 0;
    c.Stamp0 = this->Stamps[v0.idx()];
    c.Stamp1 = this->Stamps[v1.idx()];
    return c;
  }

  // One direction of an edge. `single`: its other direction is queued or
  // parked on its own.
  void Push(Mesh::HalfedgeHandle h, bool single)
  {
    if (!this->M.status(this->M.from_vertex_handle(h)).locked())
    {
      Candidate c = this->Evaluate(h);
      c.Single = single;
      this->Queue.push(c);
    }
  }

  // An edge as one entry: its direction of least error; the other is queued
  // only if that one turns out illegal (halves the queue).
  void PushEdge(Mesh::HalfedgeHandle h, std::vector<Candidate>* into = nullptr)
  {
    const Mesh::HalfedgeHandle o = this->M.opposite_halfedge_handle(h);
    const bool hFree = !this->M.status(this->M.from_vertex_handle(h)).locked();
    const bool oFree = !this->M.status(this->M.from_vertex_handle(o)).locked();
    if (!hFree && !oFree)
    {
      return;
    }
    Candidate c = hFree ? this->Evaluate(h) : this->Evaluate(o);
    if (hFree && oFree)
    {
      const Candidate other = this->Evaluate(o);
      if (other.Error < c.Error)
      {
        c = other;
      }
    }
    c.Single = !(hFree && oFree);
    if (into)
    {
      into->push_back(c);
    }
    else
    {
      this->Queue.push(c);
    }
  }

  // After a collapse into v: the halfedges at v get new entries (their error
  // changed), and the parked halfedges at v's neighbours are tried again.
  void Touch(Mesh::VertexHandle v)
  {
    this->Stamps[v.idx()] = ++this->Clock;
    for (const Mesh::HalfedgeHandle h : this->M.voh_range(v))
    {
      const Mesh::HalfedgeHandle o = this->M.opposite_halfedge_handle(h);
      this->Parked[h.idx()] = this->Parked[o.idx()] = 0;
      this->PushEdge(h);
      for (const Mesh::HalfedgeHandle g : this->M.voh_range(this->M.to_vertex_handle(h)))
      {
        for (const Mesh::HalfedgeHandle k : { g, this->M.opposite_halfedge_handle(g) })
        {
          if (this->Parked[k.idx()])
          {
            this->Parked[k.idx()] = 0;
            this->Push(k, true);
          }
        }
      }
    }
  }

  // The topological conditions under which a halfedge collapse keeps the
  // mesh a manifold of the same genus with the same boundaries, then the
  // constraints.
  bool Legal(const CollapseInfo& ci)
  {
    if (this->M.status(ci.v0).locked())
    {
      return false;
    }
    // A boundary vertex moves only along its boundary, and only through a
    // boundary edge.
    if (this->M.is_boundary(ci.v0) &&
      (!this->M.is_boundary(ci.v1) || (ci.vl.is_valid() && ci.vr.is_valid())))
    {
      return false;
    }
    // v0 must have at least two faces.
    if (this->M.cw_rotated_halfedge_handle(this->M.cw_rotated_halfedge_handle(ci.v0v1)) == ci.v0v1)
    {
      return false;
    }
    // The constraints before the link condition: on noisy surfaces they
    // reject most candidates (the normal deviation, 391,000 of 871,000 on
    // Foot at 25 %), and they are cheaper.
    for (auto& module : this->Modules)
    {
      if (module->collapse_priority(ci) < 0.0f)
      {
        return false;
      }
    }
    if (!this->M.is_collapse_ok(ci.v0v1))
    {
      return false;
    }
    // Two valence-3 tips joined by an edge: the collapse would fold a
    // tetrahedron flat.
    return !(ci.vl.is_valid() && ci.vr.is_valid() && this->M.valence(ci.vl) == 3 &&
      this->M.valence(ci.vr) == 3 && this->M.find_halfedge(ci.vl, ci.vr).is_valid());
  }

  Mesh& M;
  std::vector<OpenMesh::Geometry::Quadricd> Quadrics;
  std::vector<unsigned> Stamps;
  unsigned Clock = 0;
  std::vector<char> Parked; // per halfedge: found illegal, not queued
  std::priority_queue<Candidate> Queue;
  std::vector<std::unique_ptr<OpenMesh::Decimater::ModBaseT<Mesh>>> Modules;
  std::unique_ptr<Hausdorff> Bound;
  std::vector<int> BoundParked; // halfedges the bound parked since the last Relax
  float LastError = 0.0f;       // of the last collapse taken
};
} // namespace

vtkStandardNewMacro(vtkOpenMeshDecimation);

namespace
{
// The polygons and strips of `input` that are not ghost cells (DUPLICATECELL
// in vtkGhostType: another piece's, as a distributed pipeline hands them
// over), on the input's points; `interface` flags the points they share with
// ghost cells (the piece's border with its neighbours). Null when the input
// has no ghost polygons or strips.
vtkSmartPointer<vtkPolyData> OwnedCells(vtkPolyData* input, std::vector<char>& interface)
{
  vtkUnsignedCharArray* ghosts = input->GetCellGhostArray();
  if (!ghosts)
  {
    return nullptr;
  }
  const vtkIdType points = input->GetNumberOfPoints();
  std::vector<char> owned(static_cast<std::size_t>(points), 0), ghost(owned);
  vtkNew<vtkCellArray> cells[2];
  vtkIdType id = input->GetNumberOfVerts() + input->GetNumberOfLines(); // polygons first
  bool any = false;
  vtkCellArray* arrays[2] = { input->GetPolys(), input->GetStrips() };
  for (int k = 0; k < 2; ++k)
  {
    auto it = vtk::TakeSmartPointer(arrays[k]->NewIterator());
    for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell(), ++id)
    {
      vtkIdList* ids = it->GetCurrentCell();
      const bool isGhost = (ghosts->GetValue(id) & vtkDataSetAttributes::DUPLICATECELL) != 0;
      any = any || isGhost;
      for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i)
      {
        const vtkIdType p = ids->GetId(i);
        if (p >= 0 && p < points)
        {
          (isGhost ? ghost : owned)[static_cast<std::size_t>(p)] = 1;
        }
      }
      if (!isGhost)
      {
        cells[k]->InsertNextCell(ids);
      }
    }
  }
  if (!any)
  {
    return nullptr;
  }
  interface.assign(static_cast<std::size_t>(points), 0);
  for (std::size_t p = 0; p < interface.size(); ++p)
  {
    interface[p] = owned[p] && ghost[p];
  }
  vtkNew<vtkPolyData> result;
  result->SetPoints(input->GetPoints());
  result->GetPointData()->ShallowCopy(input->GetPointData());
  result->SetPolys(cells[0]);
  result->SetStrips(cells[1]);
  return result;
}
} // namespace

int vtkOpenMeshDecimation::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  this->AchievedReduction = 0.0;
  this->HausdorffBound = 0.0;
  if (!input || input->GetNumberOfPolys() + input->GetNumberOfStrips() == 0)
  {
    // One piece of several may hold nothing (a rank's part of a surface
    // that lies elsewhere): an empty output, not an error.
    vtkInformation* outInfo = outputVector->GetInformationObject(0);
    if (input && outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES()) > 1)
    {
      return 1;
    }
    vtkErrorMacro(<< "The input has no polygons to decimate.");
    return 1;
  }
  if (input->GetNumberOfVerts() + input->GetNumberOfLines() > 0)
  {
    vtkWarningMacro(<< "Vertices and lines of the input are ignored.");
  }
  // A piece of a distributed surface decimates the triangles it owns; its
  // border with the other pieces is locked, so that both sides keep it and
  // the pieces still meet.
  std::vector<char> interface;
  const vtkSmartPointer<vtkPolyData> owned = OwnedCells(input, interface);
  if (owned)
  {
    if (owned->GetNumberOfPolys() + owned->GetNumberOfStrips() == 0)
    {
      return 1; // only ghost cells: this piece has nothing of its own
    }
    input = owned;
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
  for (const Mesh::VertexHandle v : mesh.vertices())
  {
    const bool border =
      !interface.empty() && interface[static_cast<std::size_t>(mesh.property(originalId, v))];
    if (border || (!this->BoundaryVertexDeletion && mesh.is_boundary(v)))
    {
      mesh.status(v).set_locked(true);
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
    case LAZY:
    {
      // The largest distances come from the last collapses: the bound applies
      // from half the input's triangles, or four times the target's if that
      // is later, which keeps its bookkeeping small.
      const std::size_t boundFrom = this->AdaptiveHausdorff && this->HausdorffTolerance == 0.0
        ? std::min(facesIn / 2, 4 * (targetVertices > 0 ? 2 * targetVertices : targetFaces))
        : 0;
      LazyDecimater lazy(mesh, constraints);
      lazy.Decimate(targetVertices, targetFaces, boundFrom, triangles->GetLength(), observer);
      this->HausdorffBound = lazy.GetBound();
      break;
    }
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
  this->AchievedReduction =
    1.0 - static_cast<double>(mesh.n_faces()) / static_cast<double>(facesIn);
  this->UpdateProgress(1.0);
  return 1;
}

void vtkOpenMeshDecimation::PrintSelf(ostream& os, vtkIndent indent)
{
  static const char* types[] = { "Exact", "MultipleChoice", "Mixed", "Lazy" };
  this->Superclass::PrintSelf(os, indent);
  os << indent << "TargetReduction: " << this->TargetReduction << "\n";
  os << indent << "TargetNumberOfVertices: " << this->TargetNumberOfVertices << "\n";
  os << indent << "DecimaterType: " << types[this->DecimaterType] << "\n";
  os << indent << "MaximumNormalDeviation: " << this->MaximumNormalDeviation << "\n";
  os << indent << "HausdorffTolerance: " << this->HausdorffTolerance << "\n";
  os << indent << "AdaptiveHausdorff: " << this->AdaptiveHausdorff << "\n";
  os << indent << "MaximumAspectRatio: " << this->MaximumAspectRatio << "\n";
  os << indent << "BoundaryVertexDeletion: " << this->BoundaryVertexDeletion << "\n";
  os << indent << "AchievedReduction: " << this->AchievedReduction << "\n";
  os << indent << "HausdorffBound: " << this->HausdorffBound << "\n";
}
