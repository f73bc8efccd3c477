#include "mspline/structure/topology/cut_to_disk.h"

#include <algorithm>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "mspline/structure/core/errors.h"
#include "mspline/structure/topology/canonical_schema.h"
#include "mspline/structure/topology/cut_along_edges.h"
#include "mspline/structure/topology/cut_graph.h"
#include "mspline/structure/topology/growing_surface.h"
#include "mspline/structure/topology/homotopy_basis.h"
#include "mspline/structure/topology/one_vertex_loops.h"
#include "mspline/structure/topology/open_surface.h"
#include "mspline/structure/topology/topology.h"

namespace mspline::structure {

namespace {

/// The general cut graph. Where every path to a boundary must pass another boundary vertex, the
/// cut graph touches a boundary off its anchor and the surface falls apart; refining makes room
/// (rarely needed).
std::vector<int> generalCutEdges(GrowingSurface& work, const HomotopyBasis& basis,
                                 const HomotopyBasisOptions& basisOptions) {
  for (;;) {
    const HomotopyBasis current =
        work.refinements == 0 ? basis : computeHomotopyBasis(*work.surface, basisOptions);
    std::vector<int> cutEdges = computeCutGraph(*work.surface, current).edges;
    const TopologyReport opened = analyzeTopology(cutAlongEdges(*work.surface, cutEdges).mesh);
    if (opened.euler == 1 && opened.boundaryLoops == 1 && opened.components == 1) return cutEdges;
    std::vector<std::vector<int>> noPaths;
    refineSurface(work, noPaths);
  }
}

std::string curveName(char letter, int number) {
  return letter + std::to_string(number);
}

void fillWord(CutResult& result) {
  result.word.clear();
  for (const auto& segment : result.segments) {
    if (!result.word.empty()) result.word += ' ';
    result.word += result.curveNames[segment.curve];
    if (segment.orientation < 0) result.word += "^-1";
  }
}

void fillSegments(CutResult& result, const OpenedSurface& opened) {
  for (std::size_t k = 0; k < opened.segmentBegins.size(); ++k) {
    BoundarySegment segment;
    segment.begin = opened.segmentBegins[k];
    segment.end = k + 1 < opened.segmentBegins.size() ? opened.segmentBegins[k + 1] : 0;
    result.segments.push_back(segment);
  }
}

/// General cut: curves are the chains of the cut graph (c_k) and of the boundary (d_k).
void describeGeneralCut(CutResult& result, const OpenedSurface& opened) {
  fillSegments(result, opened);
  std::map<VertexPair, std::size_t> curveOfEdge;
  int cutChains = 0, boundaryChains = 0;
  for (std::size_t k = 0; k < result.segments.size(); ++k) {
    const std::vector<int> vertices = segmentVertices(opened, k);
    const VertexPair first = edgeKey(vertices[0], vertices[1]);
    const bool onBoundary = result.surface.is_boundary(
        TriMesh::EdgeHandle(edgeBetween(result.surface, vertices[0], vertices[1])));
    auto& segment = result.segments[k];
    segment.boundary = onBoundary;
    const auto found = curveOfEdge.find(first);
    if (found == curveOfEdge.end()) {
      segment.curve = result.curves.size();
      segment.orientation = 1;
      for (std::size_t p = 0; p + 1 < vertices.size(); ++p)
        curveOfEdge[edgeKey(vertices[p], vertices[p + 1])] = segment.curve;
      result.curves.push_back(vertices);
      result.curveNames.push_back(onBoundary ? curveName('d', ++boundaryChains)
                                             : curveName('c', ++cutChains));
    } else {
      segment.curve = found->second;
      const auto& curve = result.curves[segment.curve];
      segment.orientation =
          std::equal(vertices.begin(), vertices.end(), curve.rbegin(), curve.rend()) ? -1 : 1;
    }
  }
  fillWord(result);
}

void describeLoopCut(CutResult& result, const LoopSystem& system, const OpenedSurface& opened) {
  const LoopWord word = readLoopWord(system, opened);
  const std::size_t n = word.loop.size();
  const long rotation = canonicalRotation(word);
  result.canonical = rotation != -1;
  // Curve order and direction: a1 b1 a2 b2 ... read from the rotation when canonical, otherwise
  // x_k in order of first appearance.
  const std::size_t shift = result.canonical ? static_cast<std::size_t>(rotation) : 0;
  std::vector<long> curveOfLoop(system.loops.size(), -1);
  std::vector<int> flip(system.loops.size(), 1);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t s = (shift + k) % n;
    const int loop = word.loop[s];
    if (curveOfLoop[loop] != -1) continue;
    curveOfLoop[loop] = static_cast<long>(result.curves.size());
    flip[loop] = word.sign[s];
    std::vector<int> curve = system.loops[loop];
    if (flip[loop] < 0) std::reverse(curve.begin(), curve.end());
    result.curves.push_back(curve);
    const int number = static_cast<int>(result.curves.size());
    result.curveNames.push_back(result.canonical
                                    ? curveName(number % 2 ? 'a' : 'b', (number + 1) / 2)
                                    : curveName('x', number));
  }
  // Rotate the boundary loop so that it starts at the first segment of the word.
  const std::size_t offset = opened.segmentBegins[shift];
  std::rotate(result.boundaryLoop.begin(), result.boundaryLoop.begin() + static_cast<long>(offset),
              result.boundaryLoop.end());
  const std::size_t length = result.boundaryLoop.size();
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t s = (shift + k) % n;
    BoundarySegment segment;
    segment.begin = (opened.segmentBegins[s] + length - offset) % length;
    segment.end = (opened.segmentBegins[(s + 1) % n] + length - offset) % length;
    segment.curve = static_cast<std::size_t>(curveOfLoop[word.loop[s]]);
    segment.orientation = word.sign[s] * flip[word.loop[s]];
    result.segments.push_back(segment);
  }
  fillWord(result);
}

}  // namespace

CutResult cutToDisk(const TriMesh& mesh, const CutOptions& options) {
  HomotopyBasisOptions basisOptions;
  basisOptions.baseVertex = options.baseVertex;
  const HomotopyBasis basis = computeHomotopyBasis(mesh, basisOptions);

  const std::size_t maxVertices =
      std::max<std::size_t>(options.maxGrowth * mesh.n_vertices(), 100000);
  GrowingSurface work{std::make_unique<TriMesh>(mesh), 0, 0, options.maxRefinements, maxVertices};
  const bool loopCut = options.oneVertexSchema && basis.boundaryLoops.empty() && basis.genus > 0;
  LoopSystem system;
  std::vector<int> cutEdges;
  std::string notCanonicalBecause;
  if (loopCut) {
    system = buildOneVertexLoops(work, basis);
    if (options.canonicalSchema) {
      // Canonical form re-routes loops through the disk, which on a surface of high genus for its
      // resolution (cheese.off: genus 133, 8,600 vertices) outgrows the budget; the one-vertex
      // schema is then kept as it was built.
      GrowingSurface built{std::make_unique<TriMesh>(*work.surface), work.refinements,
                           work.edgeSplits, work.maxRefinements, work.maxVertices};
      LoopSystem builtSystem = system;
      try {
        canonicalizeLoops(work, system);
      } catch (const SolverError& error) {
        notCanonicalBecause = error.what();
        work = std::move(built);
        system = std::move(builtSystem);
      }
    }
    cutEdges = edgesOfPaths(*work.surface, system.loops);
  } else {
    cutEdges = generalCutEdges(work, basis, basisOptions);
  }
  const OpenedSurface opened = openSurface(*work.surface, cutEdges);

  CutResult result(opened.cut.mesh, *work.surface);
  result.genus = basis.genus;
  result.refinements = work.refinements;
  result.edgeSplits = work.edgeSplits;
  result.surfaceVertex = opened.cut.sourceVertex;
  result.cutEdges = opened.cutEdges;
  result.boundaryLoop = opened.boundaryLoop;
  const int inputVertices = static_cast<int>(mesh.n_vertices());
  for (int v : result.surfaceVertex) result.inputVertex.push_back(v < inputVertices ? v : -1);
  result.notCanonicalBecause = notCanonicalBecause;
  if (loopCut) {
    result.oneVertexSchema = true;
    result.baseVertex = system.center;
    describeLoopCut(result, system, opened);
  } else {
    result.baseVertex = basis.baseVertex;
    describeGeneralCut(result, opened);
  }

  const TopologyReport disk = analyzeTopology(result.disk);
  result.diskEuler = disk.euler;
  result.diskBoundaryLoops = disk.boundaryLoops;
  result.diskComponents = disk.components;
  MSPLINE_ASSERT(disk.euler == 1 && disk.boundaryLoops == 1 && disk.components == 1,
                 "the cut surface is not a disk");
  return result;
}

}  // namespace mspline::structure
