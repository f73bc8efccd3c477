#include "mspline/io/quality_report.h"

#include <sstream>

#include <nlohmann/json.hpp>

namespace mspline::io {

namespace {

// Ordered: the keys print in the order they are set.
using Json = nlohmann::ordered_json;

// A place on the surface; null when there is none.
Json locationJson(const spline::SurfaceLocation& at) {
  if (at.parameter.face < 0 || !at.position.allFinite()) return nullptr;
  return {{"position", {at.position.x(), at.position.y(), at.position.z()}},
          {"face", at.parameter.face},
          {"uv", {at.parameter.position.x(), at.parameter.position.y()}}};
}

Json spreadJson(const spline::DistanceSpread& spread) {
  return {{"count", spread.count},
          {"rms", spread.rms},
          {"p99", spread.p99},
          {"max", spread.max},
          {"max_at", locationJson(spread.maxAt)}};
}

Json dihedralJson(const spline::DihedralPercentiles& d) {
  return {{"resolution", d.resolution},
          {"pairs", d.pairs},
          {"p50", d.p50},
          {"p99", d.p99},
          {"p99_9", d.p999},
          {"max", d.max},
          {"max_at", locationJson(d.maxAt)}};
}

}  // namespace

std::string qualityJson(const spline::SurfaceQuality& quality) {
  const spline::SurfaceFolds& folds = quality.folds;
  const spline::SurfaceSmoothness& smooth = quality.smoothness;
  const spline::SurfaceRegularity& regularity = quality.regularity;
  Json out{{"with_scan", quality.withScan}};
  if (quality.withScan) {
    const spline::SurfaceDistances& d = quality.distances;
    out["distances"] = {{"diagonal", d.diagonal},
                        {"scan_to_surface", spreadJson(d.scanToSurface)},
                        {"surface_to_scan", spreadJson(d.surfaceToScan)},
                        {"unconverged_projections", d.unconvergedProjections}};
  }
  out["folds"] = {{"total", folds.total()},
                  {"against_scan", folds.againstScan},
                  {"at_scan_folds", folds.atScanFolds},
                  {"triangles", folds.triangles},
                  {"fraction", folds.fraction},
                  {"worst_against_scan", locationJson(folds.worstAgainstScan)},
                  {"worst_against_scan_degrees", folds.worstAgainstScanDegrees},
                  {"adjacent_pairs", folds.adjacentPairs},
                  {"worst_pair", locationJson(folds.worstPair)}};
  out["smoothness"] = {{"coarse", dihedralJson(smooth.coarse)},
                       {"fine", dihedralJson(smooth.fine)},
                       {"p99_ratio", smooth.p99Ratio ? Json(*smooth.p99Ratio) : Json(nullptr)},
                       {"creases", smooth.creases},
                       {"crease_degrees", smooth.creaseDegrees}};
  out["regularity"] = {{"samples", regularity.samples},
                       {"median_jacobian", regularity.medianJacobian},
                       {"min_relative_jacobian", regularity.minRelativeJacobian},
                       {"min_at", locationJson(regularity.minAt)}};
  out["seconds"] = quality.seconds;
  return out.dump();
}

std::string qualitySummary(const spline::SurfaceQuality& quality) {
  std::ostringstream out;
  if (quality.withScan) {
    const spline::SurfaceDistances& d = quality.distances;
    out << "scan to surface rms " << d.scanToSurface.rms << " max " << d.scanToSurface.max
        << ", surface to scan rms " << d.surfaceToScan.rms << " max " << d.surfaceToScan.max
        << " of the diagonal; ";
  }
  const spline::SurfaceSmoothness& smooth = quality.smoothness;
  out << quality.folds.total() << " folds; dihedral p99 " << smooth.coarse.p99 << " / "
      << smooth.fine.p99 << " deg at resolutions " << smooth.coarse.resolution << " / "
      << smooth.fine.resolution << " (ratio ";
  if (smooth.p99Ratio)
    out << *smooth.p99Ratio;
  else
    out << "none: flat";
  out << "), max " << smooth.fine.max << " deg; smallest area element "
      << quality.regularity.minRelativeJacobian << " of the median";
  return out.str();
}

}  // namespace mspline::io
