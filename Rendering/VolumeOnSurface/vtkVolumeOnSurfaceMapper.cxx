#include "vtkVolumeOnSurfaceMapper.h"

#include "vtkCamera.h"
#include "vtkCellArray.h"
#include "vtkDataArray.h"
#include "vtkIdTypeArray.h"
#include "vtkImageData.h"
#include "vtkInformation.h"
#include "vtkMatrix4x4.h"
#include "vtkObjectFactory.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkOpenGLState.h"
#include "vtkOpenMeshDecimation.h"
#include "vtkPlane.h"
#include "vtkPlaneCollection.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkRenderWindow.h"
#include "vtkRenderer.h"
#include "vtkSMPThreadLocal.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"
#include "vtkTimerLog.h"
#include "vtkUnsignedCharArray.h"
#include "vtkVolumeProperty.h"

#include "avosVolumeRay.h"

#include <algorithm>
#include <array>
#include <atomic>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <queue>
#include <string>
#include <utility>
#include <vector>

namespace
{
using Colour = std::array<unsigned char, 4>;

// How the full surface's vertices take their colours from a level's (whose
// vertices are a subset of them): each other vertex from the level's
// vertices nearest along the surface's edges to it and to its neighbours
// (a multi-source Dijkstra: their Voronoi cells on the mesh), weighted by
// the inverse of their distance, a convex combination of those colours.
struct Spread
{
  std::vector<vtkIdType> Offsets; // per full vertex, into Sources and Weights; empty: not built
  std::vector<vtkIdType> Sources; // full ids of the level's vertices
  std::vector<double> Weights;

  // The polygons' edges, both ways, as adjacency lists (CSR): vertex v's
  // neighbours are neighbours[first[v] .. first[v + 1]).
  static void Adjacency(
    vtkPolyData* full, std::vector<vtkIdType>& first, std::vector<vtkIdType>& neighbours)
  {
    const vtkIdType n = full->GetNumberOfPoints();
    first.assign(static_cast<std::size_t>(n) + 1, 0);
    auto edges = [&](auto&& visit)
    {
      full->GetPolys()->Visit(
        [&](auto& state)
        {
          for (vtkIdType cell = 0; cell < state.GetNumberOfCells(); ++cell)
          {
            const auto ids = state.GetCellRange(cell);
            const vtkIdType size = ids.size();
            for (vtkIdType k = 0; k < size; ++k)
            {
              visit(static_cast<vtkIdType>(ids[k]), static_cast<vtkIdType>(ids[(k + 1) % size]));
            }
          }
        });
    };
    edges(
      [&](vtkIdType a, vtkIdType b)
      {
        ++first[static_cast<std::size_t>(a) + 1];
        ++first[static_cast<std::size_t>(b) + 1];
      });
    for (std::size_t v = 0; v < static_cast<std::size_t>(n); ++v)
    {
      first[v + 1] += first[v];
    }
    std::vector<vtkIdType> fill(first.begin(), first.end() - 1);
    neighbours.assign(static_cast<std::size_t>(first.back()), 0);
    edges(
      [&](vtkIdType a, vtkIdType b)
      {
        neighbours[static_cast<std::size_t>(fill[static_cast<std::size_t>(a)]++)] = b;
        neighbours[static_cast<std::size_t>(fill[static_cast<std::size_t>(b)]++)] = a;
      });
  }

  // The nearest level vertex (owner) of every vertex along the edges, and
  // its distance. Each vertex settles once (a distance only ever
  // decreases), so the loop ends.
  static void Nearest(const std::vector<glm::dvec3>& points, const std::vector<vtkIdType>& first,
    const std::vector<vtkIdType>& neighbours, const std::vector<vtkIdType>& levelIds,
    std::vector<double>& distance, std::vector<vtkIdType>& owner)
  {
    distance.assign(points.size(), VTK_DOUBLE_MAX);
    owner.assign(points.size(), -1);
    using Entry = std::pair<double, vtkIdType>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
    for (vtkIdType id : levelIds)
    {
      distance[static_cast<std::size_t>(id)] = 0.0;
      owner[static_cast<std::size_t>(id)] = id;
      queue.emplace(0.0, id);
    }
    while (!queue.empty())
    {
      const Entry top = queue.top();
      queue.pop();
      const std::size_t u = static_cast<std::size_t>(top.second);
      if (top.first > distance[u])
      {
        continue;
      }
      for (vtkIdType k = first[u]; k < first[u + 1]; ++k)
      {
        const std::size_t w = static_cast<std::size_t>(neighbours[static_cast<std::size_t>(k)]);
        const double through = top.first + glm::length(points[w] - points[u]);
        if (through < distance[w])
        {
          distance[w] = through;
          owner[w] = owner[u];
          queue.emplace(through, static_cast<vtkIdType>(w));
        }
      }
    }
  }

  void Build(vtkPolyData* full, const std::vector<vtkIdType>& levelIds)
  {
    const vtkIdType n = full->GetNumberOfPoints();
    std::vector<glm::dvec3> points(static_cast<std::size_t>(n));
    for (vtkIdType v = 0; v < n; ++v)
    {
      double p[3];
      full->GetPoint(v, p);
      points[static_cast<std::size_t>(v)] = glm::dvec3(p[0], p[1], p[2]);
    }
    std::vector<vtkIdType> first, neighbours;
    Adjacency(full, first, neighbours);
    std::vector<double> distance;
    std::vector<vtkIdType> owner;
    Nearest(points, first, neighbours, levelIds, distance, owner);
    // Each vertex: its own colour on the level, else the owners of it and
    // of its neighbours (none in a part of the surface without a level
    // vertex: such a vertex gets its own ray).
    this->Offsets.assign(1, 0);
    this->Sources.clear();
    this->Weights.clear();
    for (std::size_t u = 0; u < static_cast<std::size_t>(n); ++u)
    {
      const std::size_t begin = this->Sources.size();
      auto add = [&](vtkIdType o)
      {
        if (o < 0 ||
          std::find(this->Sources.begin() + static_cast<std::ptrdiff_t>(begin), this->Sources.end(),
            o) != this->Sources.end())
        {
          return;
        }
        this->Sources.push_back(o);
        const double d = glm::length(points[static_cast<std::size_t>(o)] - points[u]);
        this->Weights.push_back(d > 0.0 ? 1.0 / d : 1.0);
      };
      add(owner[u]);
      for (vtkIdType k = first[u]; distance[u] > 0.0 && k < first[u + 1]; ++k)
      {
        add(owner[static_cast<std::size_t>(neighbours[static_cast<std::size_t>(k)])]);
      }
      this->Offsets.push_back(static_cast<vtkIdType>(this->Sources.size()));
    }
  }

  // The weighted mean of the colours of v's sources that are known; false
  // when none is.
  bool Mean(vtkIdType v, const std::vector<Colour>& colours,
    const std::vector<unsigned char>& known, Colour& mean) const
  {
    double sum[4] = { 0.0, 0.0, 0.0, 0.0 }, total = 0.0;
    for (vtkIdType k = this->Offsets[static_cast<std::size_t>(v)];
         k < this->Offsets[static_cast<std::size_t>(v) + 1]; ++k)
    {
      const std::size_t source =
        static_cast<std::size_t>(this->Sources[static_cast<std::size_t>(k)]);
      if (known[source])
      {
        const double w = this->Weights[static_cast<std::size_t>(k)];
        for (int c = 0; c < 4; ++c)
        {
          sum[c] += w * colours[source][c];
        }
        total += w;
      }
    }
    if (!(total > 0.0))
    {
      return false;
    }
    for (int c = 0; c < 4; ++c)
    {
      mean[c] = static_cast<unsigned char>(std::lround(std::min(sum[c] / total, 255.0)));
    }
    return true;
  }
};

// A level of detail: the surface drawn, and for each of its vertices the id
// of the same vertex on the full surface.
struct Level
{
  vtkSmartPointer<vtkPolyData> Surface;
  std::vector<vtkIdType> FullIds;
  Spread FromLevel; // the full surface's colours from this level's (DrawFullSurface)
};

// What a vertex's colour depends on besides the vertex itself.
struct ViewKey
{
  std::array<double, 16> Projection{};
  std::array<double, 3> Eye{};
  bool Parallel = false;
  vtkMTimeType Surface = 0, Volume = 0, Property = 0;
  // method, step, tolerance, extinction, skipping, visibility, full surface
  // drawn, volume side
  std::array<double, 8> Integration{};
  std::vector<double> Planes;  // each clipping plane's origin and normal
  std::vector<double> Shading; // the lights and coefficients, when the property shades

  bool operator==(const ViewKey& o) const
  {
    return this->Projection == o.Projection && this->Eye == o.Eye && this->Parallel == o.Parallel &&
      this->Surface == o.Surface && this->Volume == o.Volume && this->Property == o.Property &&
      this->Integration == o.Integration && this->Planes == o.Planes && this->Shading == o.Shading;
  }
};

// Which vertices get a ray: front-facing (their normal towards the eye) and
// inside the view frustum.
struct VertexView
{
  const double* M; // world to clip coordinates, row-major
  glm::dvec3 Eye;
  glm::dvec3 TowardsEye; // for a parallel projection
  bool Parallel;

  glm::dvec4 Clip(const glm::dvec3& p) const
  {
    const double* m = this->M;
    return glm::dvec4(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3],
      m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7], m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11],
      m[12] * p.x + m[13] * p.y + m[14] * p.z + m[15]);
  }

  // The unit direction from p towards the eye.
  glm::dvec3 Line(const glm::dvec3& p) const
  {
    return this->Parallel ? this->TowardsEye : glm::normalize(this->Eye - p);
  }

  // True when the vertex at p with normal n is cast; `line` its unit
  // direction towards the eye.
  bool Casts(const glm::dvec3& p, const glm::dvec3& n, glm::dvec3& line) const
  {
    line = this->Line(p);
    const glm::dvec4 c = this->Clip(p);
    return glm::dot(n, line) > 0.0 && c.w > 0.0 && std::abs(c.x) <= c.w && std::abs(c.y) <= c.w &&
      std::abs(c.z) <= c.w;
  }

  // The same for vertex v of `surface`, whose point normals are `normals`;
  // `point` its position.
  bool Casts(vtkPolyData* surface, vtkDataArray* normals, vtkIdType v, glm::dvec3& point,
    glm::dvec3& line) const
  {
    double p[3], n[3];
    surface->GetPoint(v, p);
    normals->GetTuple(v, n);
    point = glm::dvec3(p[0], p[1], p[2]);
    return this->Casts(point, glm::dvec3(n[0], n[1], n[2]), line);
  }
};

// For each vertex of `surface`, whether `view` casts it (1) or not (0).
std::vector<unsigned char> CastVertices(vtkPolyData* surface, const VertexView& view)
{
  const vtkIdType n = surface->GetNumberOfPoints();
  vtkDataArray* normals = surface->GetPointData()->GetNormals();
  std::vector<unsigned char> cast(static_cast<std::size_t>(n));
  vtkSMPTools::For(0, n,
    [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType v = begin; v < end; ++v)
      {
        glm::dvec3 point, line;
        cast[static_cast<std::size_t>(v)] = view.Casts(surface, normals, v, point, line) ? 1 : 0;
      }
    });
  return cast;
}

// Covered pixels per cast vertex of `surface` on a width x height viewport:
// the window area of its front-facing polygons with a vertex in the frustum,
// over its vertices that get a ray (`cast`, CastVertices). Hidden layers
// count in both, so the ratio is the spacing of the vertices on the screen,
// about twice a triangle's area. Infinite when no vertex is cast.
double ScreenPixelsPerVertex(vtkPolyData* surface, const std::vector<unsigned char>& cast,
  const VertexView& view, int width, int height)
{
  const vtkIdType n = surface->GetNumberOfPoints();
  std::vector<glm::dvec2> window(static_cast<std::size_t>(n));
  std::atomic<vtkIdType> count(0);
  vtkSMPTools::For(0, n,
    [&](vtkIdType begin, vtkIdType end)
    {
      vtkIdType local = 0;
      for (vtkIdType v = begin; v < end; ++v)
      {
        const std::size_t i = static_cast<std::size_t>(v);
        local += cast[i];
        double p[3];
        surface->GetPoint(v, p);
        const glm::dvec4 c = view.Clip(glm::dvec3(p[0], p[1], p[2]));
        // Behind the eye: no window position, and its polygons are skipped.
        window[i] = c.w > 0.0
          ? glm::dvec2((0.5 * c.x / c.w + 0.5) * width, (0.5 * c.y / c.w + 0.5) * height)
          : glm::dvec2(std::numeric_limits<double>::quiet_NaN());
      }
      count += local;
    });
  if (count == 0)
  {
    return std::numeric_limits<double>::infinity();
  }
  // Polygons straight from the cell array's storage (vtkCellArray::Visit).
  vtkSMPThreadLocal<double> areas;
  surface->GetPolys()->Visit(
    [&](auto& state)
    {
      vtkSMPTools::For(0, state.GetNumberOfCells(),
        [&](vtkIdType begin, vtkIdType end)
        {
          double& area = areas.Local();
          for (vtkIdType cell = begin; cell < end; ++cell)
          {
            const auto ids = state.GetCellRange(cell);
            const vtkIdType size = ids.size();
            bool inside = false;
            double twice = 0.0; // a fan's doubled signed area (counter-clockwise: front)
            for (vtkIdType k = 0; k < size; ++k)
            {
              inside = inside || cast[static_cast<std::size_t>(ids[k])];
              if (k >= 2)
              {
                const glm::dvec2 o = window[static_cast<std::size_t>(ids[0])];
                const glm::dvec2 e1 = window[static_cast<std::size_t>(ids[k - 1])] - o;
                const glm::dvec2 e2 = window[static_cast<std::size_t>(ids[k])] - o;
                twice += e1.x * e2.y - e1.y * e2.x;
              }
            }
            if (inside && twice > 0.0)
            {
              area += 0.5 * twice;
            }
          }
        });
    });
  double area = 0.0;
  for (double a : areas)
  {
    area += a;
  }
  return area / static_cast<double>(count);
}

// The depth buffer under the renderer after `draw` was drawn into it, depth
// only (the colour buffer untouched), over the renderer's tiled area
// (x0, y0, width, height). False when the window cannot give it.
template <typename Draw>
bool DepthWith(vtkRenderer* ren, Draw&& draw, std::vector<float>& depth, int area[4])
{
  auto* window = vtkOpenGLRenderWindow::SafeDownCast(ren->GetRenderWindow());
  if (!window)
  {
    return false;
  }
  {
    vtkOpenGLState* state = window->GetState();
    vtkOpenGLState::ScopedglColorMask saved(state);
    state->vtkglColorMask(false, false, false, false);
    draw();
  }
  ren->GetTiledSizeAndOrigin(&area[2], &area[3], &area[0], &area[1]);
  depth.resize(static_cast<std::size_t>(area[2]) * static_cast<std::size_t>(area[3]));
  return area[2] > 0 && area[3] > 0 &&
    window->GetZbufferData(
      area[0], area[1], area[0] + area[2] - 1, area[1] + area[3] - 1, depth.data()) != 0;
}

// The polygons of `surface` with a corner in `cast`, into `shown`. The
// others have no colour, every corner transparent black: drawn, they would
// cost the draw (most of a frame in software OpenGL) to put black over
// whatever lies behind them, which on a closed surface hides them anyway.
// Then every corner of a shown polygon joins `cast`: a corner facing away
// (on small, noisy surface fragments, or along a silhouette) would
// otherwise stay black and darken the polygon drawn; its ray, from the
// corner away from the observer, is as well defined as its neighbours'.
void ShownPolygons(vtkPolyData* surface, std::vector<unsigned char>& cast, vtkCellArray* shown)
{
  shown->Reset();
  std::vector<unsigned char> corners(cast.size(), 0);
  surface->GetPolys()->Visit(
    [&](auto& state)
    {
      for (vtkIdType cell = 0; cell < state.GetNumberOfCells(); ++cell)
      {
        const auto ids = state.GetCellRange(cell);
        if (std::any_of(ids.begin(), ids.end(),
              [&](vtkIdType id) { return cast[static_cast<std::size_t>(id)] != 0; }))
        {
          shown->InsertNextCell(static_cast<int>(ids.size()));
          for (const auto id : ids)
          {
            shown->InsertCellPoint(id);
            corners[static_cast<std::size_t>(id)] = 1;
          }
        }
      }
    });
  for (std::size_t v = 0; v < cast.size(); ++v)
  {
    cast[v] |= corners[v];
  }
}

// The vertices of `surface` that need a ray after a depth pass: those `view`
// casts (`cast`) that are not hidden, and every vertex sharing a polygon
// with one, so that a polygon with a visible corner is coloured whole.
// Hidden: at each pixel of the 3 x 3 around the vertex the depth buffer
// holds something more than `margin` (world units along the view direction)
// in front of it.
// The margin and the neighbourhood keep a vertex's own polygons, which
// reach it between pixel centres, from hiding it. `P` is the camera's
// projection (eye to clip coordinates, row-major): it turns window depths
// into distances.
std::vector<unsigned char> NeededVertices(vtkPolyData* surface, const VertexView& view,
  const std::vector<unsigned char>& cast, const double* P, const std::vector<float>& depth,
  const int area[4], double margin)
{
  const vtkIdType n = surface->GetNumberOfPoints();
  // Distance in front of the eye of an NDC depth (-1 near, 1 far).
  auto distance = [P](double z) { return -(P[11] - z * P[15]) / (z * P[14] - P[10]); };
  const int w = area[2], h = area[3];
  std::vector<unsigned char> seen(static_cast<std::size_t>(n), 0);
  vtkSMPTools::For(0, n,
    [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType v = begin; v < end; ++v)
      {
        if (!cast[static_cast<std::size_t>(v)])
        {
          continue;
        }
        double p[3];
        surface->GetPoint(v, p);
        const glm::dvec4 c = view.Clip(glm::dvec3(p[0], p[1], p[2]));
        const double own = distance(c.z / c.w) - margin;
        const int px = static_cast<int>(std::floor((0.5 * c.x / c.w + 0.5) * w));
        const int py = static_cast<int>(std::floor((0.5 * c.y / c.w + 0.5) * h));
        bool hidden = true;
        for (int y = std::max(py - 1, 0); hidden && y <= std::min(py + 1, h - 1); ++y)
        {
          for (int x = std::max(px - 1, 0); hidden && x <= std::min(px + 1, w - 1); ++x)
          {
            const double d = 2.0 * depth[static_cast<std::size_t>(y) * w + x] - 1.0;
            hidden = distance(d) < own;
          }
        }
        seen[static_cast<std::size_t>(v)] = hidden ? 0 : 1;
      }
    });
  std::vector<unsigned char> needed(seen);
  surface->GetPolys()->Visit(
    [&](auto& state)
    {
      for (vtkIdType cell = 0; cell < state.GetNumberOfCells(); ++cell)
      {
        const auto ids = state.GetCellRange(cell);
        bool any = false;
        for (const auto id : ids)
        {
          any = any || seen[static_cast<std::size_t>(id)];
        }
        for (const auto id : ids)
        {
          needed[static_cast<std::size_t>(id)] |= any ? 1 : 0;
        }
      }
    });
  return needed;
}

// Casts the rays of the full surface's vertices `ids` (distinct) into
// `colours` and `known`, in parallel, in batches whose empty-space walks run
// together; returns how many. A non-empty `failure` says why a ray could not
// be integrated (or the scalars cannot be read).
vtkIdType CastRays(vtkPolyData* full, const VertexView& view, bool parallel,
  const std::vector<vtkIdType>& ids, const avos::VolumeRaySetup& setup,
  std::vector<Colour>& colours, std::vector<unsigned char>& known, std::string& failure)
{
  if (ids.empty())
  {
    return 0;
  }
  std::atomic<vtkIdType> rays(0);
  avos::RayFailures failures;
  auto cast = [&](const auto& caster)
  {
    vtkSMPTools::For(0, static_cast<vtkIdType>(ids.size()),
      [&](vtkIdType begin, vtkIdType end)
      {
        constexpr std::size_t batch = 64;
        std::array<vtkIdType, batch> queued;
        std::array<glm::dvec3, batch> points, lines;
        std::array<double, batch> reaches;
        std::array<avos::numerics::RayResult<double>, batch> results;
        std::size_t count = 0;
        vtkIdType local = 0;
        auto flush = [&]()
        {
          caster.Cast(count, points.data(), lines.data(), reaches.data(), results.data());
          for (std::size_t i = 0; i < count; ++i)
          {
            if (!results[i].Error.empty())
            {
              failures.Add(results[i].Error);
              continue;
            }
            const std::size_t v = static_cast<std::size_t>(queued[i]);
            colours[v] = avos::ToBytes(results[i].RGBA);
            known[v] = 1;
            ++local;
          }
          count = 0;
        };
        for (vtkIdType i = begin; i < end; ++i)
        {
          const vtkIdType v = ids[static_cast<std::size_t>(i)];
          double p[3];
          full->GetPoint(v, p);
          const glm::dvec3 point(p[0], p[1], p[2]);
          queued[count] = v;
          points[count] = point;
          // Behind: from the vertex away from the observer, to the volume's
          // far boundary; in front: towards the observer, at most to the eye.
          const bool behind = setup.Side == avos::VolumeSide::Behind;
          lines[count] = behind ? -view.Line(point) : view.Line(point);
          reaches[count] = behind || parallel ? VTK_DOUBLE_MAX : glm::length(view.Eye - point);
          if (++count == batch)
          {
            flush();
          }
        }
        flush();
        rays += local;
      });
  };
  if (!setup.Dispatch(cast))
  {
    failure = std::string("unsupported scalar type ") + setup.Scalars->GetDataTypeAsString();
    return 0;
  }
  if (failures.GetCount() > 0)
  {
    failure = failures.GetMessage();
  }
  return rays;
}

// What one surface drawn (a level, or the full surface with
// DrawFullSurface) hands its OpenGL delegate: the surface (a shallow copy)
// with its colours, written in place each view, and only its polygons with
// a cast corner (ShownPolygons). One per surface drawn, kept while the
// levels are: a level drawn again, as the automatic level goes back and
// forth between views, finds its geometry already uploaded.
struct Drawing
{
  vtkNew<vtkPolyData> Drawn;
  vtkNew<vtkUnsignedCharArray> Colors;
  vtkNew<vtkUnsignedCharArray> Display; // their RGB: what is drawn, opaque
  vtkNew<vtkPolyData> Shown;
  vtkNew<vtkCellArray> ShownPolys;
  vtkSmartPointer<vtkPolyDataMapper> Delegate;

  // The colours start black: a depth pass draws them before they are
  // written.
  explicit Drawing(vtkPolyData* surface)
  {
    this->Drawn->ShallowCopy(surface);
    this->Colors->SetName("VoSColors");
    this->Colors->SetNumberOfComponents(4);
    this->Colors->SetNumberOfTuples(surface->GetNumberOfPoints());
    this->Colors->Fill(0);
    this->Drawn->GetPointData()->SetScalars(this->Colors);
    this->Display->SetName("VoSDisplayColors");
    this->Display->SetNumberOfComponents(3);
    this->Display->SetNumberOfTuples(surface->GetNumberOfPoints());
    this->Display->Fill(0);
    this->Drawn->GetPointData()->AddArray(this->Display);
    this->Shown->ShallowCopy(this->Drawn);
    this->Shown->SetPolys(this->ShownPolys);
    // The OpenGL implementation, through VTK's object factory, drawing
    // opaque by the colours' RGB (premultiplied: the volume in front over
    // black, as a ray cast shows it); RGBA would be blended, multiplying the
    // colour by its opacity once more.
    this->Delegate = vtkSmartPointer<vtkPolyDataMapper>::New();
    this->Delegate->SetColorModeToDirectScalars();
    this->Delegate->SetScalarModeToUsePointFieldData();
    this->Delegate->SelectColorArray("VoSDisplayColors");
    this->Delegate->SetInputData(this->Shown);
  }
};

// The key of the full surface's Drawing (DrawFullSurface); the levels' are
// their indices.
constexpr int FullSurface = -1;
} // namespace

class vtkVolumeOnSurfaceMapper::vtkInternals
{
public:
  std::vector<double> Reductions{ 0.0, 0.5, 0.9 };
  std::vector<Level> Levels;
  vtkPolyData* LevelsSource = nullptr;
  vtkMTimeType LevelsTime = 0;

  // Colours on the full surface's vertex ids for the view `Key`: computed
  // ones are reused by every level.
  ViewKey Key;
  bool HaveKey = false;
  std::vector<Colour> FullColors;
  std::vector<unsigned char> Known;
  int DrawnLevel = -1;
  double SecondsPerRay = 0.0;
  // The depth pass: its last cost (seconds, the draw and the read back) and
  // the share of the candidate vertices it found hidden; new views since
  // it last ran.
  double PassSeconds = 0.0;
  double HiddenShare = 1.0;
  int ViewsWithoutPass = 16;         // the first view measures the pass
  double FullPixelsPerVertex = -1.0; // the full surface's for the view `Key`; < 0: unknown
  avos::EmptySpaceCache EmptySpace;
  avos::EngineVolume EngineScalars;

  // This frame's inputs (ValidateInputs), its view and key (UpdateView:
  // NextKey becomes Key when the view is new), and the first level's cast
  // vertices when ChooseLevel computed them.
  vtkPolyData* Surface = nullptr;
  vtkImageData* Volume = nullptr;
  ViewKey NextKey;
  VertexView View{};
  std::vector<unsigned char> FirstCast;

  // What colouring a level passes from stage to stage.
  struct Pass
  {
    bool Spread = false;               // the full surface drawn, the level's colours spread
    vtkPolyData* Drawn = nullptr;      // the level's surface or the full one
    std::vector<unsigned char> Cast;   // per drawn vertex: it faces the eye
    std::vector<unsigned char> Needed; // per drawn vertex: not hidden; empty: no depth pass
    std::vector<Colour> SpreadColors;  // per drawn vertex, when spread
    const avos::VolumeRaySetup* Setup = nullptr; // while CastLevelRays runs

    // A drawn vertex wants a colour when it is cast and not hidden.
    bool Wants(vtkIdType d) const
    {
      const std::size_t i = static_cast<std::size_t>(d);
      return this->Cast[i] && (this->Needed.empty() || this->Needed[i]);
    }
  };
  Pass Current;

  // The surfaces drawn so far, by level (FullSurface: the full one), and
  // the one drawn last (null before the first).
  std::map<int, std::unique_ptr<Drawing>> Drawings;
  Drawing* Active = nullptr;
  vtkNew<vtkPolyData> Nothing; // GetColoredSurface() before a surface is coloured

  // Gives the drawings' OpenGL resources back.
  void ReleaseGraphics(vtkWindow* win)
  {
    for (auto& drawing : this->Drawings)
    {
      drawing.second->Delegate->ReleaseGraphicsResources(win);
    }
  }

  // Gives the drawings' OpenGL resources back and forgets them.
  void ReleaseDrawings(vtkWindow* win)
  {
    this->ReleaseGraphics(win);
    this->Drawings.clear();
    this->Active = nullptr;
  }
};

vtkStandardNewMacro(vtkVolumeOnSurfaceMapper);
vtkCxxSetObjectMacro(vtkVolumeOnSurfaceMapper, VolumeProperty, vtkVolumeProperty);

vtkVolumeOnSurfaceMapper::vtkVolumeOnSurfaceMapper()
  : Internals(new vtkInternals)
{
  this->SetNumberOfInputPorts(2);
}

vtkVolumeOnSurfaceMapper::~vtkVolumeOnSurfaceMapper()
{
  this->SetVolumeProperty(nullptr);
}

void vtkVolumeOnSurfaceMapper::SetVolumeConnection(vtkAlgorithmOutput* output)
{
  this->SetInputConnection(1, output);
}

void vtkVolumeOnSurfaceMapper::SetVolumeData(vtkImageData* volume)
{
  this->SetInputDataInternal(1, volume);
}

void vtkVolumeOnSurfaceMapper::AddLevelOfDetailReduction(double reduction)
{
  this->Internals->Reductions.push_back(reduction);
  this->Internals->Levels.clear();
  this->Modified();
}

void vtkVolumeOnSurfaceMapper::RemoveAllLevelOfDetailReductions()
{
  this->Internals->Reductions.clear();
  this->Internals->Levels.clear();
  this->Modified();
}

vtkIdType vtkVolumeOnSurfaceMapper::GetVolumeMemory()
{
  auto* volume = this->GetNumberOfInputConnections(1) > 0
    ? vtkImageData::SafeDownCast(this->GetInputDataObject(1, 0))
    : nullptr;
  bool cellScalars = false;
  vtkDataArray* scalars = avos::VolumeScalars(volume, cellScalars);
  // GetActualMemorySize() is in KiB.
  return scalars ? static_cast<vtkIdType>(scalars->GetActualMemorySize()) * 1024 : 0;
}

vtkIdType vtkVolumeOnSurfaceMapper::GetSurfaceMemory(int level)
{
  const std::vector<Level>& levels = this->Internals->Levels;
  if (level < 0 || level >= static_cast<int>(levels.size()))
  {
    return 0;
  }
  vtkPolyData* s = levels[static_cast<std::size_t>(level)].Surface;
  vtkDataArray* normals = s->GetPointData()->GetNormals();
  return static_cast<vtkIdType>(s->GetPoints()->GetData()->GetActualMemorySize() +
           (normals ? normals->GetActualMemorySize() : 0) + s->GetPolys()->GetActualMemorySize()) *
    1024 +
    7 * s->GetNumberOfPoints();
}

double vtkVolumeOnSurfaceMapper::GetScreenPixelsPerVertex()
{
  return this->Internals->FullPixelsPerVertex;
}

int vtkVolumeOnSurfaceMapper::GetNumberOfLevelsOfDetail()
{
  return static_cast<int>(this->Internals->Reductions.size());
}

vtkPolyData* vtkVolumeOnSurfaceMapper::GetColoredSurface()
{
  vtkInternals& in = *this->Internals;
  return in.Active ? in.Active->Drawn.Get() : in.Nothing.Get();
}

int vtkVolumeOnSurfaceMapper::FillInputPortInformation(int port, vtkInformation* info)
{
  info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), port == 0 ? "vtkPolyData" : "vtkImageData");
  return 1;
}

void vtkVolumeOnSurfaceMapper::ReleaseGraphicsResources(vtkWindow* win)
{
  this->Internals->ReleaseGraphics(win);
}

void vtkVolumeOnSurfaceMapper::Render(vtkRenderer* ren, vtkActor* act)
{
  vtkInternals& in = *this->Internals;
  this->NumberOfRaysCast = 0;
  this->NumberOfReusedColors = 0;
  vtkNew<vtkTimerLog> timer;
  timer->StartTimer();
  if (!this->ValidateInputs() || !this->UpdateLevels(ren))
  {
    return;
  }
  const bool newView = this->UpdateView(ren);
  const int level = this->ChooseLevel(ren, newView);
  if (newView)
  {
    this->StartView();
  }
  if (level != in.DrawnLevel && !this->ColourLevel(ren, act, level))
  {
    in.HaveKey = false; // nothing coloured: the next frame starts again
    return;
  }
  this->LastLevelOfDetail = level;
  timer->StopTimer();
  this->ColoringTime = timer->GetElapsedTime();
  if (this->NumberOfRaysCast > 0)
  {
    in.SecondsPerRay =
      std::max(0.0, this->ColoringTime - (this->LastDepthPass ? in.PassSeconds : 0.0)) /
      static_cast<double>(this->NumberOfRaysCast);
  }
  if (in.Active)
  {
    in.Active->Delegate->SetClippingPlanes(this->ClippingPlanes);
    in.Active->Delegate->Render(ren, act);
  }
}

bool vtkVolumeOnSurfaceMapper::ValidateInputs()
{
  vtkInternals& in = *this->Internals;
  if (this->GetNumberOfInputConnections(1) < 1)
  {
    vtkErrorMacro(<< "No volume: connect one to input port 1 (SetVolumeConnection).");
    return false;
  }
  this->GetInputAlgorithm(0, 0)->Update();
  this->GetInputAlgorithm(1, 0)->Update();
  in.Surface = this->GetInput();
  in.Volume = vtkImageData::SafeDownCast(this->GetInputDataObject(1, 0));
  if (!in.Surface || in.Surface->GetNumberOfPoints() == 0)
  {
    vtkErrorMacro(<< "The surface (input 0) is empty.");
    return false;
  }
  if (!in.Surface->GetPointData()->GetNormals())
  {
    vtkErrorMacro(<< "The surface needs point normals (vtkFlyingEdges3D::ComputeNormalsOn, or "
                     "vtkPolyDataNormals).");
    return false;
  }
  if (!this->VolumeProperty || in.Reductions.empty())
  {
    vtkErrorMacro(<< "No volume property, or no level of detail.");
    return false;
  }
  for (double r : in.Reductions)
  {
    if (!(r >= 0.0 && r < 1.0))
    {
      vtkErrorMacro(<< "Level-of-detail reductions must be in [0, 1), not " << r << ".");
      return false;
    }
  }
  return true;
}

bool vtkVolumeOnSurfaceMapper::UpdateLevels(vtkRenderer* ren)
{
  vtkInternals& in = *this->Internals;
  vtkPolyData* surface = in.Surface;
  if (!in.Levels.empty() && in.LevelsSource == surface && in.LevelsTime == surface->GetMTime())
  {
    return true;
  }
  in.Levels.clear();
  for (double r : in.Reductions)
  {
    Level level;
    if (r == 0.0)
    {
      level.Surface = surface;
      level.FullIds.resize(static_cast<std::size_t>(surface->GetNumberOfPoints()));
      for (std::size_t i = 0; i < level.FullIds.size(); ++i)
      {
        level.FullIds[i] = static_cast<vtkIdType>(i);
      }
    }
    else
    {
      vtkNew<vtkOpenMeshDecimation> decimate;
      decimate->SetInputData(surface);
      decimate->SetTargetReduction(r);
      decimate->Update();
      level.Surface = decimate->GetOutput();
      auto* ids = vtkIdTypeArray::SafeDownCast(
        level.Surface->GetPointData()->GetArray("vtkOriginalPointIds"));
      if (!ids)
      {
        vtkErrorMacro(<< "Decimating the surface to level " << r << " failed.");
        in.Levels.clear();
        return false;
      }
      level.FullIds.assign(ids->GetPointer(0), ids->GetPointer(0) + ids->GetNumberOfTuples());
    }
    in.Levels.push_back(level);
  }
  in.LevelsSource = surface;
  in.LevelsTime = surface->GetMTime();
  in.HaveKey = false;
  in.ReleaseDrawings(ren->GetRenderWindow());
  return true;
}

bool vtkVolumeOnSurfaceMapper::UpdateView(vtkRenderer* ren)
{
  vtkInternals& in = *this->Internals;
  vtkCamera* camera = ren->GetActiveCamera();
  vtkMatrix4x4* projection =
    camera->GetCompositeProjectionTransformMatrix(ren->GetTiledAspectRatio(), -1, 1);
  ViewKey& key = in.NextKey;
  key = ViewKey();
  std::copy(projection->GetData(), projection->GetData() + 16, key.Projection.begin());
  camera->GetPosition(key.Eye.data());
  key.Parallel = camera->GetParallelProjection() != 0;
  double direction[3];
  camera->GetDirectionOfProjection(direction);
  key.Surface = in.Surface->GetMTime();
  key.Volume = in.Volume->GetMTime();
  key.Property = this->VolumeProperty->GetMTime();
  key.Integration = { double(this->IntegrationMethod), this->SampleDistance, this->Tolerance,
    double(this->ExtinctionOpacity), double(this->EmptySpaceSkipping), double(this->VisibilityTest),
    double(this->DrawFullSurface), double(this->VolumeSide) };
  if (this->ClippingPlanes)
  {
    vtkCollectionSimpleIterator it;
    this->ClippingPlanes->InitTraversal(it);
    while (vtkPlane* plane = this->ClippingPlanes->GetNextPlane(it))
    {
      const double* o = plane->GetOrigin();
      const double* n = plane->GetNormal();
      key.Planes.insert(key.Planes.end(), { o[0], o[1], o[2], n[0], n[1], n[2] });
    }
  }
  if (this->VolumeProperty->GetShade(0))
  {
    // (A light that cannot be used is reported by ColourLevel's Prepare.)
    avos::numerics::ShadingModel<double> model;
    avos::ShadingFromRenderer(ren, this->VolumeProperty, model, key.Shading);
  }
  // The view points into the key's own storage, which lives as long as it.
  in.View = VertexView{ key.Projection.data(), glm::dvec3(key.Eye[0], key.Eye[1], key.Eye[2]),
    -glm::dvec3(direction[0], direction[1], direction[2]), key.Parallel };
  return !in.HaveKey || !(key == in.Key);
}

int vtkVolumeOnSurfaceMapper::ChooseLevel(vtkRenderer* ren, bool newView)
{
  // Forced, or the coarser of two: the finest whose estimated colouring
  // time fits the frame time the window asks for, and the coarsest whose
  // cast vertices are still at most PixelsPerVertex covered pixels apart
  // (more vertices add rays, not detail the screen can show).
  vtkInternals& in = *this->Internals;
  const int levels = static_cast<int>(in.Levels.size());
  in.FirstCast.clear();
  if (this->LevelOfDetail >= 0)
  {
    return std::min(this->LevelOfDetail, levels - 1);
  }
  const double rate = ren->GetRenderWindow()->GetDesiredUpdateRate();
  const double budget = rate > 0.0 ? 1.0 / rate : VTK_DOUBLE_MAX;
  int fits = levels - 1;
  for (int l = 0; l < levels; ++l)
  {
    if (in.SecondsPerRay * in.Levels[l].Surface->GetNumberOfPoints() <= budget)
    {
      fits = l;
      break;
    }
  }
  if (newView || in.FullPixelsPerVertex < 0.0)
  {
    const int* size = ren->GetSize();
    in.FirstCast = CastVertices(in.Levels[0].Surface, in.View);
    in.FullPixelsPerVertex =
      ScreenPixelsPerVertex(in.Levels[0].Surface, in.FirstCast, in.View, size[0], size[1]);
  }
  int dense = 0;
  const double full = static_cast<double>(in.Levels[0].Surface->GetNumberOfPoints());
  for (int l = levels - 1; this->PixelsPerVertex > 0.0 && l > 0; --l)
  {
    const double points = static_cast<double>(in.Levels[l].Surface->GetNumberOfPoints());
    if (in.FullPixelsPerVertex * full / points <= this->PixelsPerVertex)
    {
      dense = l;
      break;
    }
  }
  return std::max(fits, dense);
}

void vtkVolumeOnSurfaceMapper::StartView()
{
  vtkInternals& in = *this->Internals;
  in.FullColors.assign(static_cast<std::size_t>(in.Surface->GetNumberOfPoints()), { 0, 0, 0, 0 });
  in.Known.assign(in.FullColors.size(), 0);
  in.Key = in.NextKey;
  in.HaveKey = true;
  in.FullPixelsPerVertex = this->LevelOfDetail < 0 ? in.FullPixelsPerVertex : -1.0;
  in.DrawnLevel = -1;
}

bool vtkVolumeOnSurfaceMapper::ColourLevel(vtkRenderer* ren, vtkActor* act, int levelIndex)
{
  vtkInternals& in = *this->Internals;
  avos::VolumeRaySetup setup;
  // The mapper's clipping planes clip the drawn surface (the delegate) and
  // cut the rays: no volume from beyond a plane colours a vertex.
  const std::string error =
    setup.Prepare(in.Volume, this->VolumeProperty, this->ExtinctionOpacity != 0,
      static_cast<avos::RayIntegration>(this->IntegrationMethod), this->SampleDistance,
      this->Tolerance, this->ClippingPlanes, ren->GetLights(), ren->GetTwoSidedLighting() != 0);
  if (!avos::ReportPrepared(this, error, setup))
  {
    return false;
  }
  setup.Side = static_cast<avos::VolumeSide>(this->VolumeSide);
  avos::UseCaches(this, setup, in.EmptySpace, in.EngineScalars, this->EmptySpaceSkipping != 0);
  this->SelectDrawing(levelIndex);
  this->TestVisibility(ren, act);
  in.Current.Setup = &setup;
  std::string failure;
  this->CastLevelRays(levelIndex, failure);
  in.Current.Setup = nullptr;
  if (!failure.empty())
  {
    // No silent transparent vertices: nothing is drawn.
    vtkErrorMacro(<< failure << ".");
    return false;
  }
  this->StoreColours(levelIndex);
  in.DrawnLevel = levelIndex;
  return true;
}

void vtkVolumeOnSurfaceMapper::SelectDrawing(int levelIndex)
{
  // The surface drawn: the level's, or the full one whose other vertices
  // take their colours from the level's (DrawFullSurface). A drawn vertex is
  // known by its index there, a ray by its full id. (The levels need not
  // include the full surface: their reductions are the user's.)
  vtkInternals& in = *this->Internals;
  vtkInternals::Pass& pass = in.Current;
  Level& level = in.Levels[static_cast<std::size_t>(levelIndex)];
  pass.Spread = this->DrawFullSurface && level.Surface.Get() != in.Surface;
  pass.Drawn = pass.Spread ? in.Surface : level.Surface.Get();
  if (pass.Spread && level.FromLevel.Offsets.empty())
  {
    level.FromLevel.Build(pass.Drawn, level.FullIds);
  }
  std::unique_ptr<Drawing>& slot = in.Drawings[pass.Spread ? FullSurface : levelIndex];
  if (!slot)
  {
    slot.reset(new Drawing(pass.Drawn));
  }
  in.Active = slot.get();
  // (The first level's, when ChooseLevel computed them.)
  pass.Cast = pass.Drawn == in.Levels[0].Surface && !in.FirstCast.empty()
    ? std::move(in.FirstCast)
    : CastVertices(pass.Drawn, in.View);
  ShownPolygons(pass.Drawn, pass.Cast, in.Active->ShownPolys);
  in.Active->Delegate->SetClippingPlanes(this->ClippingPlanes);
}

void vtkVolumeOnSurfaceMapper::TestVisibility(vtkRenderer* ren, vtkActor* act)
{
  // The depth pass: DEPTH always; AUTO when the rays it saved last time (at
  // today's cost per ray) outweigh what it cost, and every 16th new view to
  // measure again.
  vtkInternals& in = *this->Internals;
  vtkInternals::Pass& pass = in.Current;
  const double saving =
    in.HiddenShare * static_cast<double>(this->NumberOfVisibleVertices) * in.SecondsPerRay;
  const bool depthPass = this->VisibilityTest == DEPTH_VISIBILITY ||
    (this->VisibilityTest == AUTOMATIC_VISIBILITY &&
      (in.PassSeconds < saving || in.ViewsWithoutPass >= 16));
  pass.Needed.clear();
  this->LastDepthPass = 0;
  if (!depthPass)
  {
    ++in.ViewsWithoutPass;
    return;
  }
  vtkNew<vtkTimerLog> passTimer;
  passTimer->StartTimer();
  std::vector<float> depth;
  int area[4];
  double spacing[3];
  in.Volume->GetSpacing(spacing);
  Drawing& drawing = *in.Active;
  if (DepthWith(
        ren, [&]() { drawing.Delegate->Render(ren, act); }, depth, area))
  {
    vtkMatrix4x4* eyeToClip =
      ren->GetActiveCamera()->GetProjectionTransformMatrix(ren->GetTiledAspectRatio(), -1, 1);
    pass.Needed = NeededVertices(pass.Drawn, in.View, pass.Cast, eyeToClip->GetData(), depth, area,
      std::max({ std::abs(spacing[0]), std::abs(spacing[1]), std::abs(spacing[2]) }));
    this->LastDepthPass = 1;
  }
  passTimer->StopTimer();
  in.PassSeconds = passTimer->GetElapsedTime();
  in.ViewsWithoutPass = 0;
}

void vtkVolumeOnSurfaceMapper::CastLevelRays(int levelIndex, std::string& failure)
{
  vtkInternals& in = *this->Internals;
  vtkInternals::Pass& pass = in.Current;
  const avos::VolumeRaySetup& setup = *pass.Setup;
  const Level& level = in.Levels[static_cast<std::size_t>(levelIndex)];
  // The level's vertices that need a ray (full ids), and the counts.
  vtkIdType visible = 0, reused = 0, hidden = 0;
  std::vector<vtkIdType> wanted;
  for (std::size_t v = 0; v < level.FullIds.size(); ++v)
  {
    const vtkIdType full = level.FullIds[v];
    const vtkIdType d = pass.Spread ? full : static_cast<vtkIdType>(v);
    if (!pass.Cast[static_cast<std::size_t>(d)])
    {
      continue;
    }
    ++visible;
    if (!pass.Wants(d))
    {
      ++hidden;
    }
    else if (in.Known[static_cast<std::size_t>(full)])
    {
      ++reused;
    }
    else
    {
      wanted.push_back(full);
    }
  }
  const bool parallel = in.Key.Parallel;
  vtkIdType rays =
    CastRays(in.Surface, in.View, parallel, wanted, setup, in.FullColors, in.Known, failure);
  // The full surface's other vertices: the colours of the level's around
  // them (Spread), or their own ray where none of those was cast (beside a
  // silhouette, the level's vertices there may all face away).
  pass.SpreadColors.clear();
  if (pass.Spread && failure.empty())
  {
    const std::vector<vtkIdType> orphans = this->SpreadColours(levelIndex);
    rays +=
      CastRays(in.Surface, in.View, parallel, orphans, setup, in.FullColors, in.Known, failure);
  }
  this->NumberOfRaysCast = rays;
  this->NumberOfVisibleVertices = visible;
  this->NumberOfReusedColors = reused;
  this->NumberOfHiddenVertices = hidden;
  if (this->LastDepthPass && visible > 0)
  {
    in.HiddenShare = static_cast<double>(hidden) / static_cast<double>(visible);
  }
}

std::vector<vtkIdType> vtkVolumeOnSurfaceMapper::SpreadColours(int levelIndex)
{
  vtkInternals& in = *this->Internals;
  vtkInternals::Pass& pass = in.Current;
  const Level& level = in.Levels[static_cast<std::size_t>(levelIndex)];
  pass.SpreadColors.assign(
    static_cast<std::size_t>(pass.Drawn->GetNumberOfPoints()), { 0, 0, 0, 0 });
  std::vector<unsigned char> orphan(pass.SpreadColors.size(), 0);
  vtkSMPTools::For(0, pass.Drawn->GetNumberOfPoints(),
    [&](vtkIdType begin, vtkIdType end)
    {
      for (vtkIdType d = begin; d < end; ++d)
      {
        const std::size_t i = static_cast<std::size_t>(d);
        orphan[i] = pass.Wants(d) && !in.Known[i] &&
            !level.FromLevel.Mean(d, in.FullColors, in.Known, pass.SpreadColors[i])
          ? 1
          : 0;
      }
    });
  std::vector<vtkIdType> orphans;
  for (std::size_t i = 0; i < orphan.size(); ++i)
  {
    if (orphan[i])
    {
      orphans.push_back(static_cast<vtkIdType>(i));
    }
  }
  return orphans;
}

void vtkVolumeOnSurfaceMapper::StoreColours(int levelIndex)
{
  vtkInternals& in = *this->Internals;
  const vtkInternals::Pass& pass = in.Current;
  const Level& level = in.Levels[static_cast<std::size_t>(levelIndex)];
  Drawing& drawing = *in.Active;
  unsigned char* rgba = drawing.Colors->GetPointer(0);
  unsigned char* rgb = drawing.Display->GetPointer(0);
  for (vtkIdType d = 0; d < pass.Drawn->GetNumberOfPoints(); ++d)
  {
    const std::size_t full =
      static_cast<std::size_t>(pass.Spread ? d : level.FullIds[static_cast<std::size_t>(d)]);
    const auto& c = in.Known[full] || pass.SpreadColors.empty()
      ? in.FullColors[full]
      : pass.SpreadColors[static_cast<std::size_t>(d)];
    std::copy(c.begin(), c.end(), rgba + 4 * d);
    std::copy(c.begin(), c.begin() + 3, rgb + 3 * d);
  }
  drawing.Colors->Modified();
  drawing.Display->Modified();
}

void vtkVolumeOnSurfaceMapper::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "VolumeProperty: " << this->VolumeProperty << "\n";
  const char* methods[3] = { "Levoy", "Adaptive", "Piecewise" };
  os << indent << "IntegrationMethod: " << methods[this->IntegrationMethod] << "\n";
  os << indent << "VolumeSide: "
     << (this->VolumeSide == BEHIND_SURFACE ? "BehindSurface" : "InFrontOfSurface") << "\n";
  os << indent << "SampleDistance: " << this->SampleDistance << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
  os << indent << "ExtinctionOpacity: " << this->ExtinctionOpacity << "\n";
  os << indent << "EmptySpaceSkipping: " << this->EmptySpaceSkipping << "\n";
  os << indent << "LevelOfDetailReductions:";
  for (double r : this->Internals->Reductions)
  {
    os << " " << r;
  }
  os << "\n" << indent << "LevelOfDetail: " << this->LevelOfDetail << "\n";
  os << indent << "PixelsPerVertex: " << this->PixelsPerVertex << "\n";
  const char* tests[3] = { "Off", "Depth", "Automatic" };
  os << indent << "VisibilityTest: " << tests[this->VisibilityTest] << "\n";
  os << indent << "DrawFullSurface: " << this->DrawFullSurface << "\n";
  os << indent << "LastDepthPass: " << this->LastDepthPass << "\n";
  os << indent << "NumberOfHiddenVertices: " << this->NumberOfHiddenVertices << "\n";
  os << indent << "LastLevelOfDetail: " << this->LastLevelOfDetail << "\n";
  os << indent << "NumberOfRaysCast: " << this->NumberOfRaysCast << "\n";
  os << indent << "NumberOfVisibleVertices: " << this->NumberOfVisibleVertices << "\n";
  os << indent << "NumberOfReusedColors: " << this->NumberOfReusedColors << "\n";
  os << indent << "ColoringTime: " << this->ColoringTime << "\n";
}
