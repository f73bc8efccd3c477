#include "mspline/spline/subd/osd_patches.h"

#include <string>

#include <opensubdiv/far/patchTableFactory.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include "mspline/structure/core/errors.h"

namespace mspline::spline {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
using structure::InputError;

namespace {

// Cubic Bezier basis at s with first and second derivatives.
void bezierBasis(double s, double b[4], double d1[4], double d2[4]) {
  const double r = 1.0 - s;
  b[0] = r * r * r;
  b[1] = 3 * s * r * r;
  b[2] = 3 * s * s * r;
  b[3] = s * s * s;
  d1[0] = -3 * r * r;
  d1[1] = 3 * r * (r - 2 * s);
  d1[2] = 3 * s * (2 * r - s);
  d1[3] = 3 * s * s;
  d2[0] = 6 * r;
  d2[1] = 18 * s - 12;
  d2[2] = 6 - 18 * s;
  d2[3] = 6 * s;
}

// Weights of OpenSubdiv's 20-point Gregory basis patch at (s, t) of the patch, with the exact
// derivatives of its rational interior weights. (OpenSubdiv's own EvaluateBasis differentiates
// only the Bezier factor, which leaves its derivatives about 1% off those of the position.) The
// points come in 4 groups of 5 per corner: corner point, edge points along the corner's two edges
// (counter-clockwise first), and the two face points that blend into one Bezier interior point.
// w[0] gets the position weights, w[1], w[2] the s and t derivatives, w[3..5] (with `second`)
// the ss, st and tt derivatives.
void gregoryBasis(double s, double t, double (*w)[kMaxOsdPatchVertices], bool second) {
  static const int boundaryPoint[12] = {0, 1, 7, 5, 2, 6, 16, 12, 15, 17, 11, 10};
  static const int boundaryCol[12] = {0, 1, 2, 3, 0, 3, 0, 3, 0, 1, 2, 3};
  static const int boundaryRow[12] = {0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 3, 3};
  // Per corner: the Bezier interior point and the face point f+ weight N / D, both linear in
  // (s, t): N = n0 + ns s + nt t, D = d0 + ds s + dt t. f- gets 1 - N / D.
  static const int interiorCol[4] = {1, 2, 2, 1}, interiorRow[4] = {1, 1, 2, 2};
  static const double n0[4] = {0, 0, 1, 1}, ns[4] = {1, 0, -1, 0}, nt[4] = {0, 1, 0, -1};
  static const double d0[4] = {0, 1, 2, 1}, ds[4] = {1, -1, -1, 1}, dt[4] = {1, 1, -1, -1};

  double bs[4], bs1[4], bs2[4], bt[4], bt1[4], bt2[4];
  bezierBasis(s, bs, bs1, bs2);
  bezierBasis(t, bt, bt1, bt2);
  for (int i = 0; i < 12; ++i) {
    const int p = boundaryPoint[i], c = boundaryCol[i], r = boundaryRow[i];
    w[0][p] = bs[c] * bt[r];
    w[1][p] = bs1[c] * bt[r];
    w[2][p] = bs[c] * bt1[r];
    if (second) {
      w[3][p] = bs2[c] * bt[r];
      w[4][p] = bs1[c] * bt1[r];
      w[5][p] = bs[c] * bt2[r];
    }
  }
  for (int corner = 0; corner < 4; ++corner) {
    const double d = d0[corner] + ds[corner] * s + dt[corner] * t;
    // At the corner itself (d = 0) the Bezier factor and its first derivatives vanish; any finite
    // G will do.
    double g = 0, gs = 0, gt = 0, gss = 0, gst = 0, gtt = 0;
    if (d > 0) {
      g = (n0[corner] + ns[corner] * s + nt[corner] * t) / d;
      gs = (ns[corner] - g * ds[corner]) / d;
      gt = (nt[corner] - g * dt[corner]) / d;
      gss = -2 * gs * ds[corner] / d;
      gst = -(gs * dt[corner] + gt * ds[corner]) / d;
      gtt = -2 * gt * dt[corner] / d;
    }
    const int c = interiorCol[corner], r = interiorRow[corner];
    const double b = bs[c] * bt[r], b_s = bs1[c] * bt[r], b_t = bs[c] * bt1[r];
    // f+ with G, f- with 1 - G (whose derivatives are those of G negated).
    for (int side = 0; side < 2; ++side) {
      const int p = 5 * corner + 3 + side;
      const double sign = side == 0 ? 1.0 : -1.0;
      const double gp = side == 0 ? g : 1.0 - g;
      w[0][p] = b * gp;
      w[1][p] = b_s * gp + sign * b * gs;
      w[2][p] = b_t * gp + sign * b * gt;
      if (second) {
        const double b_ss = bs2[c] * bt[r], b_st = bs1[c] * bt1[r], b_tt = bs[c] * bt2[r];
        w[3][p] = b_ss * gp + sign * (2 * b_s * gs + b * gss);
        w[4][p] = b_st * gp + sign * (b_s * gt + b_t * gs + b * gst);
        w[5][p] = b_tt * gp + sign * (2 * b_t * gt + b * gtt);
      }
    }
  }
}

Sdc::Options::VtxBoundaryInterpolation boundaryInterpolation(BoundaryRule rule,
                                                             const char* source) {
  switch (rule) {
    case BoundaryRule::None:
      return Sdc::Options::VTX_BOUNDARY_NONE;
    case BoundaryRule::EdgeOnly:
      return Sdc::Options::VTX_BOUNDARY_EDGE_ONLY;
    case BoundaryRule::EdgeAndCorner:
      return Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER;
  }
  throw InputError(std::string(source) + ": unknown boundary rule");
}

}  // namespace

void checkIsolationLevel(const CatmullClarkOptions& options, const char* source) {
  if (options.isolationLevel < 1 || options.isolationLevel > 10)
    throw InputError(std::string(source) + ": isolation level " +
                     std::to_string(options.isolationLevel) + " is outside 1..10");
}

OsdPatches buildOsdPatches(int numVertices, const std::vector<std::vector<int>>& faces,
                           const CatmullClarkOptions& options, const char* source) {
  OsdPatches patches;
  std::vector<int> sizes, indices;
  sizes.reserve(faces.size());
  patches.firstPatchFace.assign(1, 0);
  for (const auto& face : faces) {
    const int n = static_cast<int>(face.size());
    sizes.push_back(n);
    indices.insert(indices.end(), face.begin(), face.end());
    patches.firstPatchFace.push_back(patches.firstPatchFace.back() + (n == 4 ? 1 : n));
  }
  Far::TopologyDescriptor descriptor;
  descriptor.numVertices = numVertices;
  descriptor.numFaces = static_cast<int>(faces.size());
  descriptor.numVertsPerFace = sizes.data();
  descriptor.vertIndicesPerFace = indices.data();

  Sdc::Options sdc;
  sdc.SetVtxBoundaryInterpolation(boundaryInterpolation(options.boundary, source));
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  patches.refiner.reset(Factory::Create(descriptor, Factory::Options(Sdc::SCHEME_CATMARK, sdc)));
  if (!patches.refiner)
    throw InputError(std::string(source) + ": OpenSubdiv rejected the topology");

  Far::PatchTableFactory::Options patchOptions(static_cast<unsigned>(options.isolationLevel));
  patchOptions.SetPatchPrecision<double>();
  patchOptions.endCapType = Far::PatchTableFactory::Options::ENDCAP_GREGORY_BASIS;
  patchOptions.useInfSharpPatch = true;
  patchOptions.generateLegacySharpCornerPatches = false;
  patchOptions.generateVaryingTables = false;  // only vertex data is evaluated
  patches.refiner->RefineAdaptive(patchOptions.GetRefineAdaptiveOptions());
  patches.patchTable.reset(Far::PatchTableFactory::Create(*patches.refiner, patchOptions));
  MSPLINE_ASSERT(patches.patchTable->GetNumPtexFaces() == patches.firstPatchFace.back(),
                 "OpenSubdiv counts other patch faces than the net's quads and polygon corners");
  for (int array = 0; array < patches.patchTable->GetNumPatchArrays(); ++array)
    MSPLINE_ASSERT(patches.patchTable->GetPatchArrayDescriptor(array).GetNumControlVertices() <=
                       kMaxOsdPatchVertices,
                   "patch with more control points than a Gregory basis");
  patches.patchMap = std::make_unique<Far::PatchMap>(*patches.patchTable);
  return patches;
}

Far::ConstIndexArray osdPatchWeights(const Far::PatchTable& table,
                                     const Far::PatchTable::PatchHandle& handle, double u, double v,
                                     double (*w)[kMaxOsdPatchVertices], bool second) {
  const Far::PatchParam param = table.GetPatchParam(handle);
  const Far::ConstIndexArray cvs = table.GetPatchVertices(handle);
  // The patch spans 2^-level of the patch face in each direction; level is the depth, minus one
  // on the sub-faces of non-quads, which start at depth 1.
  const double patchScale = double(1 << (param.GetDepth() - (param.NonQuadRoot() ? 1 : 0)));
  double factor = patchScale;  // from derivatives per unit of the patch
  if (table.GetPatchDescriptor(handle).GetType() == Far::PatchDescriptor::GREGORY_BASIS) {
    double s = u, t = v;
    param.Normalize(s, t);
    gregoryBasis(s, t, w, second);
  } else {
    if (second)
      table.EvaluateBasis(handle, u, v, w[0], w[1], w[2], w[3], w[4], w[5]);
    else
      table.EvaluateBasis(handle, u, v, w[0], w[1], w[2]);
    // OpenSubdiv 3.5 scales derivatives by 2^depth, which is twice too much on non-quads'
    // sub-faces.
    factor = patchScale / double(1 << param.GetDepth());
  }
  if (factor != 1.0)
    for (int i = 0; i < cvs.size(); ++i) {
      w[1][i] *= factor;
      w[2][i] *= factor;
      if (second) {
        w[3][i] *= factor * factor;
        w[4][i] *= factor * factor;
        w[5][i] *= factor * factor;
      }
    }
  return cvs;
}

}  // namespace mspline::spline
