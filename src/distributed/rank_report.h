// What each rank of a distributed render did, gathered on rank 0 for the statistics: its
// device, lanes, leaves, samples, and where its time went. MPI-free.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "src/integrator/render_api.h"

namespace pt {

struct RankReport {
  int rank = 0;
  std::string host, backend, device;
  int lanes = 0;
  int leaves = 0;             // leaves this rank rendered (whole or cut short by a stop)
  uint64_t samples = 0;
  double startupMs = 0.0;     // session creation and scene upload (all lanes, in parallel)
  double finishedMs = 0.0;    // when its last lane finished, from the common render start
  double renderMs = 0.0;      // summed over lanes: RenderRange
  double saveMs = 0.0;        // summed over lanes: film downloads
  double waitMs = 0.0;        // summed over lanes: waiting for a leaf
  double mergeMs = 0.0;       // merging films on this rank
  double sendMs = 0.0;        // from its lanes' end to its films handed on
  std::string failure;        // a lane's error, if any
  RenderStats stats;          // the lanes' statistics, summed
};

nlohmann::json RankReportToJson(const RankReport& r);
RankReport RankReportFromJson(const nlohmann::json& j);

// Adds b's counters and stage times into a (device name and backend kept from a).
void AddRenderStats(RenderStats& a, const RenderStats& b);

// The ranks' finishing times' mean over their maximum: 1 when all finished together.
double LoadBalance(const std::vector<RankReport>& ranks);

}  // namespace pt
