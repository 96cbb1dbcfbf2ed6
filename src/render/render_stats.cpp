// RenderStats: totals and the JSON stats line.
#include <nlohmann/json.hpp>

#include "rayscout/render/renderer.h"

namespace rayscout {

uint64_t RenderStats::rays() const {
  uint64_t n = 0;
  for (const auto& b : batches) n += b.rays;
  return n;
}

TraceStats RenderStats::counters() const {
  TraceStats t;
  for (const auto& b : batches) t += b.counters;
  return t;
}

double RenderStats::mrays_per_s() const { return rayscout::mrays_per_s(rays(), trace_ms); }

std::string RenderStats::to_json() const {
  using nlohmann::json;
  auto counters_json = [](const TraceStats& t) {
    return json{{"rays", t.rays}, {"traversal_steps", t.traversal_steps},
                {"ray_box_tests", t.ray_box_tests}, {"ray_tri_tests", t.ray_tri_tests}};
  };
  const bool counted = counters().rays > 0;
  json j;
  j["raygen_ms"] = raygen_ms;
  j["trace_ms"] = trace_ms;
  j["shading_ms"] = shading_ms;
  j["total_ms"] = total_ms;
  j["rays"] = rays();
  j["mrays_per_s"] = mrays_per_s();
  json list = json::array();
  for (const auto& b : batches) {
    json e{{"bounce", b.info.bounce}, {"kind", b.info.kind}, {"occlusion", b.info.occlusion},
           {"rays", b.rays}, {"trace_ms", b.trace_ms},
           {"mrays_per_s", rayscout::mrays_per_s(b.rays, b.trace_ms)}};
    if (counted) e["counters"] = counters_json(b.counters);
    list.push_back(e);
  }
  j["batches"] = list;
  // The same per bounce (all kinds of rays leaving that path vertex).
  json bounces = json::array();
  for (const auto& b : batches) {
    while (int(bounces.size()) <= b.info.bounce)
      bounces.push_back(json{{"bounce", bounces.size()}, {"rays", 0}, {"trace_ms", 0.0}});
    json& e = bounces[size_t(b.info.bounce)];
    e["rays"] = e["rays"].get<uint64_t>() + b.rays;
    e["trace_ms"] = e["trace_ms"].get<double>() + b.trace_ms;
  }
  j["bounces"] = bounces;
  if (counted) j["counters"] = counters_json(counters());
  return j.dump();
}

}  // namespace rayscout
