// vtkOpenMeshDecimation: the reduction reached within 1 % of the target for
// every decimater, genus and boundaries unchanged, boundary vertices kept,
// output vertices a subset of the input with their point data and original
// ids, the Hausdorff constraint honoured, ghost cells of a distributed
// surface left out with its pieces' border kept, and bad input reported.
#include "vtkCallbackCommand.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFlyingEdges3D.h"
#include "vtkHausdorffDistancePointSetFilter.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkNew.h"
#include "vtkOpenMeshDecimation.h"
#include "vtkPlaneSource.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkUnsignedCharArray.h"

#include "avosTestHelpers.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <iterator>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace
{
avostest::Checklist Expect;

// Euler characteristic V - E + F and the number of boundary loops of the
// triangles (V counts the vertices that triangles use).
struct Topology
{
  long Euler = 0;
  long BoundaryLoops = 0;
  long BoundaryVertices = 0;
};

Topology Measure(vtkPolyData* mesh)
{
  std::map<std::pair<vtkIdType, vtkIdType>, int> edges;
  std::set<vtkIdType> used;
  auto it = vtk::TakeSmartPointer(mesh->GetPolys()->NewIterator());
  for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
  {
    vtkIdList* ids = it->GetCurrentCell();
    for (int k = 0; k < 3; ++k)
    {
      const vtkIdType a = ids->GetId(k), b = ids->GetId((k + 1) % 3);
      ++edges[{ std::min(a, b), std::max(a, b) }];
      used.insert(a);
    }
  }
  // Boundary edges are used once; loops by union-find over their vertices.
  std::map<vtkIdType, vtkIdType> parent;
  auto find = [&](vtkIdType v)
  {
    while (parent[v] != v)
    {
      v = parent[v] = parent[parent[v]];
    }
    return v;
  };
  for (const auto& e : edges)
  {
    if (e.second == 1)
    {
      for (vtkIdType v : { e.first.first, e.first.second })
      {
        parent.emplace(v, v);
      }
      parent[find(e.first.first)] = find(e.first.second);
    }
  }
  Topology t;
  t.Euler = static_cast<long>(used.size()) - static_cast<long>(edges.size()) +
    static_cast<long>(mesh->GetNumberOfPolys());
  t.BoundaryVertices = static_cast<long>(parent.size());
  for (const auto& p : parent)
  {
    t.BoundaryLoops += find(p.first) == p.first;
  }
  return t;
}

// A torus (genus 1) from an implicit function on a grid, with normals and a
// point-data array, about 20 000 triangles.
vtkSmartPointer<vtkPolyData> Torus()
{
  vtkNew<vtkImageData> image;
  const int n = 64;
  image->SetDimensions(n, n, n);
  image->SetOrigin(-1.5, -1.5, -1.5);
  image->SetSpacing(3.0 / (n - 1), 3.0 / (n - 1), 3.0 / (n - 1));
  image->AllocateScalars(VTK_FLOAT, 1);
  auto* f = static_cast<float*>(image->GetScalarPointer());
  for (int k = 0; k < n; ++k)
  {
    for (int j = 0; j < n; ++j)
    {
      for (int i = 0; i < n; ++i)
      {
        int ijk[3] = { i, j, k };
        double p[3];
        image->GetPoint(image->ComputePointId(ijk), p);
        const double q = std::sqrt(p[0] * p[0] + p[1] * p[1]) - 1.0;
        *f++ = static_cast<float>(q * q + p[2] * p[2]);
      }
    }
  }
  vtkNew<vtkFlyingEdges3D> contour;
  contour->SetInputData(image);
  contour->SetValue(0, 0.16); // tube radius 0.4
  contour->ComputeNormalsOn();
  contour->ComputeScalarsOff();
  contour->Update();
  auto torus = vtkSmartPointer<vtkPolyData>::New();
  torus->DeepCopy(contour->GetOutput());
  vtkNew<vtkDoubleArray> height;
  height->SetName("Height");
  for (vtkIdType i = 0; i < torus->GetNumberOfPoints(); ++i)
  {
    height->InsertNextValue(torus->GetPoint(i)[2]);
  }
  torus->GetPointData()->AddArray(height);
  return torus;
}

// The symmetric Hausdorff distance, points to cells.
double HausdorffDistance(vtkPolyData* in, vtkPolyData* out)
{
  vtkNew<vtkHausdorffDistancePointSetFilter> distance;
  distance->SetInputData(0, in);
  distance->SetInputData(1, out);
  distance->SetTargetDistanceMethodToPointToCell();
  distance->Update();
  return distance->GetHausdorffDistance();
}

// Every output vertex is the input vertex its id names, with its data.
bool SubsetWithData(vtkPolyData* in, vtkPolyData* out)
{
  auto* ids = vtkIdTypeArray::SafeDownCast(out->GetPointData()->GetArray("vtkOriginalPointIds"));
  if (!ids || ids->GetNumberOfTuples() != out->GetNumberOfPoints())
  {
    return false;
  }
  std::set<vtkIdType> seen;
  for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
  {
    const vtkIdType id = ids->GetValue(i);
    if (id < 0 || id >= in->GetNumberOfPoints() || !seen.insert(id).second)
    {
      return false;
    }
    double a[3], b[3];
    out->GetPoint(i, a);
    in->GetPoint(id, b);
    if (a[0] != b[0] || a[1] != b[1] || a[2] != b[2])
    {
      return false;
    }
    for (int k = 0; k < in->GetPointData()->GetNumberOfArrays(); ++k)
    {
      vtkDataArray* source = in->GetPointData()->GetArray(k);
      vtkDataArray* carried = out->GetPointData()->GetArray(source->GetName());
      if (!carried)
      {
        return false;
      }
      for (int c = 0; c < source->GetNumberOfComponents(); ++c)
      {
        if (source->GetComponent(id, c) != carried->GetComponent(i, c))
        {
          return false;
        }
      }
    }
  }
  return true;
}
} // namespace

int TestOpenMeshDecimation(int, char*[])
{
  vtkSmartPointer<vtkPolyData> torus = Torus();
  const Topology closed = Measure(torus);
  Expect(closed.Euler == 0 && closed.BoundaryLoops == 0, "the torus is closed, genus 1");
  std::cout << "torus: " << torus->GetNumberOfPolys() << " triangles\n";

  vtkNew<vtkOpenMeshDecimation> decimate;
  decimate->SetInputData(torus);
  for (int type : { vtkOpenMeshDecimation::EXACT, vtkOpenMeshDecimation::MULTIPLE_CHOICE,
         vtkOpenMeshDecimation::MIXED, vtkOpenMeshDecimation::LAZY })
  {
    decimate->SetDecimaterType(type);
    for (double target : { 0.25, 0.5, 0.75, 0.9 })
    {
      decimate->SetTargetReduction(target);
      decimate->Update();
      vtkPolyData* out = decimate->GetOutput();
      const double achieved =
        1.0 - double(out->GetNumberOfPolys()) / double(torus->GetNumberOfPolys());
      const std::string what = "type " + std::to_string(type) + " target " + std::to_string(target);
      std::cout << what << ": achieved " << achieved << "\n";
      Expect(std::abs(achieved - target) <= 0.01, what + ": reduction within 1 %");
      Expect(std::abs(achieved - decimate->GetAchievedReduction()) < 1e-12, what + ": reported");
      const Topology t = Measure(out);
      Expect(t.Euler == 0 && t.BoundaryLoops == 0, what + ": still a closed torus");
      Expect(SubsetWithData(torus, out), what + ": vertices, data and ids carried");
    }
  }

  // Progress events while decimating, ending at 1.
  {
    std::vector<double> progress;
    vtkNew<vtkCallbackCommand> record;
    record->SetClientData(&progress);
    record->SetCallback(
      [](vtkObject*, unsigned long, void* clientData, void* callData) {
        static_cast<std::vector<double>*>(clientData)->push_back(*static_cast<double*>(callData));
      });
    decimate->AddObserver(vtkCommand::ProgressEvent, record);
    decimate->SetTargetReduction(0.6);
    decimate->SetDecimaterTypeToLazy();
    decimate->Update();
    decimate->RemoveObserver(record);
    Expect(progress.size() > 10 && progress.back() == 1.0 &&
        std::is_sorted(progress.begin(), progress.end()),
      "progress events during decimation");
  }

  // A target vertex count.
  decimate->SetDecimaterTypeToExact();
  decimate->SetTargetNumberOfVertices(1000);
  decimate->Update();
  Expect(decimate->GetOutput()->GetNumberOfPoints() == 1000, "target number of vertices");
  decimate->SetTargetNumberOfVertices(0);

  // An open, wavy sheet of quads (triangulated by the filter): one boundary
  // loop, kept vertex for vertex.
  vtkNew<vtkPlaneSource> plane;
  plane->SetResolution(60, 40);
  plane->Update();
  vtkNew<vtkPolyData> sheet;
  sheet->DeepCopy(plane->GetOutput());
  for (vtkIdType i = 0; i < sheet->GetNumberOfPoints(); ++i)
  {
    double p[3];
    sheet->GetPoint(i, p);
    p[2] = 0.1 * std::sin(6 * p[0]) * std::cos(5 * p[1]);
    sheet->GetPoints()->SetPoint(i, p);
  }
  decimate->SetInputData(sheet);
  decimate->SetTargetReduction(0.8);
  decimate->Update();
  {
    const Topology before = Measure(decimate->GetOutput()); // triangulated output
    Expect(before.Euler == 1 && before.BoundaryLoops == 1, "the sheet keeps one boundary loop");
    Expect(before.BoundaryVertices == 2 * (60 + 40), "every boundary vertex kept");
    Expect(SubsetWithData(sheet, decimate->GetOutput()), "sheet: subset with data");
    Expect(decimate->GetAchievedReduction() > 0.7, "the sheet's interior is decimated");
  }
  // The same sheet with the lazy decimater and its adaptive bound, to a
  // target the kept boundary puts out of reach: the bound relaxes until it
  // is no longer what stops the decimation, and the filter ends there.
  decimate->SetDecimaterTypeToLazy();
  decimate->SetTargetReduction(0.97);
  decimate->Update();
  {
    const Topology after = Measure(decimate->GetOutput());
    std::cout << "sheet, lazy to 97 %: achieved " << decimate->GetAchievedReduction() << ", bound "
              << decimate->GetHausdorffBound() << "\n";
    Expect(decimate->GetAchievedReduction() > 0.7 && decimate->GetAchievedReduction() < 0.97,
      "lazy: an unreachable target ends at the topological limit");
    Expect(decimate->GetHausdorffBound() > 0.0, "lazy: the bound applied on the way");
    Expect(after.Euler == 1 && after.BoundaryLoops == 1 && after.BoundaryVertices == 2 * (60 + 40),
      "lazy: the sheet keeps its boundary");
  }

  // The adaptive Hausdorff bound (LAZY, on by default): it applies only
  // beyond 50 %, is reported, and gives a surface no farther from the input
  // than without it, closer at some reduction.
  decimate->SetInputData(torus);
  decimate->SetDecimaterTypeToLazy();
  bool closer = false;
  for (double target : { 0.5, 0.9, 0.97 })
  {
    decimate->SetTargetReduction(target);
    decimate->AdaptiveHausdorffOff();
    decimate->Update();
    Expect(decimate->GetHausdorffBound() == 0.0, "no bound when off");
    const double off = HausdorffDistance(torus, decimate->GetOutput());
    decimate->AdaptiveHausdorffOn();
    decimate->Update();
    const double on = HausdorffDistance(torus, decimate->GetOutput());
    const double bound = decimate->GetHausdorffBound();
    std::cout << "adaptive bound at " << target << ": " << bound << ", Hausdorff " << on
              << " (off: " << off << "), achieved " << decimate->GetAchievedReduction() << "\n";
    Expect(std::abs(decimate->GetAchievedReduction() - target) <= 0.01,
      "the bound still reaches the target");
    Expect(target > 0.5 ? bound > 0.0 : bound == 0.0, "the bound applies beyond 50 % only");
    Expect(target > 0.5 ? on <= off : on == off, "the bound never raises the Hausdorff distance");
    closer = closer || on < off;
  }
  Expect(closer, "the bound lowers the Hausdorff distance");

  // Hausdorff constraint: no removed vertex farther than the tolerance.
  decimate->SetTargetReduction(0.95);
  decimate->SetHausdorffTolerance(0.002);
  decimate->Update();
  {
    const double d = HausdorffDistance(torus, decimate->GetOutput());
    std::cout << "Hausdorff 0.002: achieved " << decimate->GetAchievedReduction()
              << ", input-to-output distance " << d << "\n";
    Expect(decimate->GetAchievedReduction() < 0.95, "the tolerance stops the reduction");
    Expect(d >= 0.0 && d <= 0.002 * (1 + 1e-6), "removed vertices within the tolerance");
  }
  decimate->SetHausdorffTolerance(0.0);

  // Two pieces of the sheet as a distributed pipeline hands them over: each
  // its own quads (centroid left or right of x = 0) and, marked as ghost
  // cells, the other side's quads that touch them. With boundary vertex
  // deletion on (so only the border's lock keeps it), each piece's output
  // uses only its own quads' points, and both keep the same border edges.
  {
    auto centroidX = [&](vtkIdList* ids)
    {
      double x = 0.0;
      for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i)
      {
        x += sheet->GetPoint(ids->GetId(i))[0];
      }
      return x / static_cast<double>(ids->GetNumberOfIds());
    };
    std::set<vtkIdType> used[2]; // points of each side's own quads
    {
      auto it = vtk::TakeSmartPointer(sheet->GetPolys()->NewIterator());
      for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
      {
        vtkIdList* ids = it->GetCurrentCell();
        for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i)
        {
          used[centroidX(ids) < 0.0 ? 0 : 1].insert(ids->GetId(i));
        }
      }
    }
    std::set<vtkIdType> border;
    std::set_intersection(used[0].begin(), used[0].end(), used[1].begin(), used[1].end(),
      std::inserter(border, border.begin()));
    auto piece = [&](int side)
    {
      vtkNew<vtkCellArray> cells;
      vtkNew<vtkUnsignedCharArray> ghosts;
      ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
      auto it = vtk::TakeSmartPointer(sheet->GetPolys()->NewIterator());
      for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
      {
        vtkIdList* ids = it->GetCurrentCell();
        const bool own = (centroidX(ids) < 0.0) == (side == 0);
        bool touches = false;
        for (vtkIdType i = 0; i < ids->GetNumberOfIds(); ++i)
        {
          touches = touches || used[side].count(ids->GetId(i)) > 0;
        }
        if (own || touches)
        {
          cells->InsertNextCell(ids);
          ghosts->InsertNextValue(own ? 0 : vtkDataSetAttributes::DUPLICATECELL);
        }
      }
      vtkNew<vtkPolyData> result;
      result->SetPoints(sheet->GetPoints());
      result->GetPointData()->ShallowCopy(sheet->GetPointData());
      result->SetPolys(cells);
      result->GetCellData()->AddArray(ghosts);
      return vtkSmartPointer<vtkPolyData>(result);
    };
    // Boundary edges between border points, by input ids.
    auto borderEdges = [&](vtkPolyData* out)
    {
      auto* ids =
        vtkIdTypeArray::SafeDownCast(out->GetPointData()->GetArray("vtkOriginalPointIds"));
      std::map<std::pair<vtkIdType, vtkIdType>, int> edges;
      auto it = vtk::TakeSmartPointer(out->GetPolys()->NewIterator());
      for (it->GoToFirstCell(); !it->IsDoneWithTraversal(); it->GoToNextCell())
      {
        vtkIdList* tri = it->GetCurrentCell();
        for (int k = 0; k < 3; ++k)
        {
          const vtkIdType a = ids->GetValue(tri->GetId(k)),
                          b = ids->GetValue(tri->GetId((k + 1) % 3));
          ++edges[{ std::min(a, b), std::max(a, b) }];
        }
      }
      std::set<std::pair<vtkIdType, vtkIdType>> result;
      for (const auto& e : edges)
      {
        if (e.second == 1 && border.count(e.first.first) && border.count(e.first.second))
        {
          result.insert(e.first);
        }
      }
      return result;
    };
    decimate->SetDecimaterTypeToExact();
    decimate->SetTargetReduction(0.8);
    decimate->BoundaryVertexDeletionOn();
    std::set<std::pair<vtkIdType, vtkIdType>> edges[2];
    for (int side : { 0, 1 })
    {
      decimate->SetInputData(piece(side));
      decimate->Update();
      vtkPolyData* out = decimate->GetOutput();
      auto* ids =
        vtkIdTypeArray::SafeDownCast(out->GetPointData()->GetArray("vtkOriginalPointIds"));
      bool own = out->GetNumberOfPoints() > 0, keepsBorder = true;
      std::set<vtkIdType> kept;
      for (vtkIdType i = 0; i < out->GetNumberOfPoints(); ++i)
      {
        own = own && used[side].count(ids->GetValue(i)) > 0;
        kept.insert(ids->GetValue(i));
      }
      for (vtkIdType p : border)
      {
        keepsBorder = keepsBorder && kept.count(p) > 0;
      }
      edges[side] = borderEdges(out);
      const std::string what = "piece " + std::to_string(side);
      std::cout << what << ": " << out->GetNumberOfPolys() << " triangles, " << edges[side].size()
                << " border edges\n";
      Expect(own, what + ": no ghost cell decimated into the output");
      Expect(keepsBorder, what + ": every border vertex kept");
      Expect(decimate->GetAchievedReduction() > 0.6, what + ": decimated");
      Expect(out->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()) == nullptr,
        what + ": no ghost cells out");
    }
    Expect(edges[0].size() == border.size() - 1 && edges[0] == edges[1],
      "both pieces keep the same border edges: they still meet");
    decimate->BoundaryVertexDeletionOff();

    // A piece of ghost cells only: nothing of its own, an empty output.
    vtkSmartPointer<vtkPolyData> ghostsOnly = piece(0);
    auto* flags = vtkUnsignedCharArray::SafeDownCast(
      ghostsOnly->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()));
    flags->Fill(vtkDataSetAttributes::DUPLICATECELL);
    decimate->SetInputData(ghostsOnly);
    decimate->Update();
    Expect(decimate->GetOutput()->GetNumberOfPolys() == 0, "a ghost-only piece: empty output");
  }

  // Non-manifold and degenerate input: a fan of three triangles on one edge
  // and a triangle with a repeated vertex. Reported, decimated, no crash.
  avostest::ExpectedErrors errors(decimate);
  {
    vtkNew<vtkPolyData> fins;
    vtkNew<vtkPoints> points;
    const double coords[][3] = { { 0, 0, 0 }, { 1, 0, 0 }, { 0.5, 1, 0 }, { 0.5, -1, 0 },
      { 0.5, 0, 1 } };
    for (const auto& c : coords)
    {
      points->InsertNextPoint(c);
    }
    vtkNew<vtkCellArray> cells;
    const vtkIdType tris[][3] = { { 0, 1, 2 }, { 1, 0, 3 }, { 0, 1, 4 }, { 2, 2, 4 } };
    for (const auto& t : tris)
    {
      cells->InsertNextCell(3, t);
    }
    fins->SetPoints(points);
    fins->SetPolys(cells);
    decimate->SetInputData(fins);
    decimate->SetTargetReduction(0.5);
    decimate->Update();
    Expect(errors.CheckWarning("fins", "manifold"), "non-manifold faces reported");
    Expect(decimate->GetOutput()->GetNumberOfPolys() >= 1, "non-manifold input decimated");
  }

  vtkNew<vtkPolyData> empty;
  decimate->SetInputData(empty);
  decimate->Update();
  Expect(errors.Check("empty input", "no polygons"), "empty input");
  Expect(decimate->GetOutput()->GetNumberOfPoints() == 0, "empty output");
  // An empty piece of several is a rank's share of nothing: no error.
  decimate->UpdatePiece(1, 2, 0);
  Expect(errors.None("empty piece 1 of 2"), "an empty piece is no error");
  Expect(decimate->GetOutput()->GetNumberOfPoints() == 0, "an empty piece's output");

  vtkNew<vtkPolyData> withNaN;
  withNaN->DeepCopy(torus);
  withNaN->GetPoints()->SetPoint(5, std::nan(""), 0, 0);
  decimate->SetInputData(withNaN);
  decimate->Update();
  Expect(errors.Check("NaN point", "not finite"), "NaN point");
  Expect(decimate->GetOutput()->GetNumberOfPolys() == 0, "no output from NaN input");

  return Expect.Result();
}
