#include "pipeline/eval/metric_tally.h"

#include <cstdio>

namespace smokesvd::eval {
namespace {

using nlohmann::json;

json number(std::optional<double> value) { return value ? json(*value) : json(nullptr); }

std::string text(const json& value) {
  if (value.is_null()) return "";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", value.get<double>());
  return buffer;
}

// Mean over `values` of those present; nothing if none is.
std::optional<double> meanOf(const std::vector<std::optional<double>>& values) {
  double sum = 0;
  int n = 0;
  for (const auto& v : values)
    if (v) {
      sum += *v;
      ++n;
    }
  if (n == 0) return std::nullopt;
  return sum / n;
}

const char* const kImageMetrics[] = {"rmse", "psnr", "ssim"};
const char* const kTemporalMetrics[] = {"warp_error", "flow_max", "flow_mean", "flow_std"};

double temporalValue(const TemporalScores& s, int metric) {
  switch (metric) {
    case 0: return s.warpError;
    case 1: return s.flowMax;
    case 2: return s.flowMean;
    default: return s.flowStd;
  }
}

std::string resolutionText(const EvalView& view) {
  return std::to_string(view.camera.width) + "x" + std::to_string(view.camera.height);
}

}  // namespace

void ImageMeans::add(const ImageScore& score) {
  rmse += score.rmse();
  psnr += score.psnr();
  ssim += score.ssim;
  ++count;
}

std::optional<std::array<double, 3>> ImageMeans::means() const {
  if (count == 0) return std::nullopt;
  return std::array<double, 3>{rmse / count, psnr / count, ssim / count};
}

std::vector<std::string> metricsCsvHeader() {
  return {"section", "group", "metric", "ours", "reference", "floor_black", "floor_input", "views", "resolution", "units"};
}

Summary summarise(const std::vector<EvalView>& views, const std::vector<ViewTally>& tallies, const VolumeTally& volume,
                  const std::string& units) {
  Summary summary;
  summary.image = json::object();
  summary.temporal = json::object();
  json imagePerView = json::object(), temporalPerView = json::object();
  std::vector<TemporalScores> temporal[4];
  for (std::size_t v = 0; v < views.size(); ++v) {
    for (int s = 0; s < 4; ++s) temporal[s].push_back(tallies[v].temporal[static_cast<std::size_t>(s)].finish());
    json image = json::object();
    for (int m = 0; m < 3; ++m) {
      json entry;
      const char* names[] = {"ours", "floor_black", "floor_input"};
      for (int c = 0; c < 3; ++c) {
        const auto means = tallies[v].image[static_cast<std::size_t>(c)].means();
        entry[names[c]] = means ? json((*means)[static_cast<std::size_t>(m)]) : json(nullptr);
      }
      image[kImageMetrics[m]] = entry;
    }
    if (views[v].hasReference) imagePerView[views[v].name] = image;
    json t = {{"pairs", temporal[0][v].pairs}};
    for (int m = 0; m < 4; ++m) {
      const bool ref = views[v].hasReference;
      t[kTemporalMetrics[m]] = {{"ours", temporalValue(temporal[kSequenceOurs][v], m)},
                                {"reference", ref ? json(temporalValue(temporal[kSequenceReference][v], m)) : json(nullptr)},
                                {"floor_black", ref ? json(temporalValue(temporal[kSequenceBlack][v], m)) : json(nullptr)},
                                {"floor_input", ref && views[v].group != ViewGroup::Input
                                                    ? json(temporalValue(temporal[kSequenceInput][v], m))
                                                    : json(nullptr)}};
    }
    temporalPerView[views[v].name] = t;
  }
  const bool flow = opticalFlowAvailable();
  for (ViewGroup group : {ViewGroup::Input, ViewGroup::Side, ViewGroup::Novel}) {
    std::vector<std::size_t> members;
    json names = json::array();
    std::string resolution;
    for (std::size_t v = 0; v < views.size(); ++v)
      if (views[v].group == group) {
        members.push_back(v);
        names.push_back(views[v].name);
        resolution = resolutionText(views[v]);
      }
    if (members.empty()) continue;
    const std::string groupName = eval::groupName(group);
    std::string viewList;
    for (const auto& n : names) {
      if (!viewList.empty()) viewList += ' ';
      viewList += n.get<std::string>();
    }
    json imageGroup = {{"views", names}};
    bool anyImage = false;
    std::vector<std::vector<std::string>> imageRows;
    for (int m = 0; m < 3; ++m) {
      json entry;
      const char* keys[] = {"ours", "floor_black", "floor_input"};
      for (int c = 0; c < 3; ++c) {
        std::vector<std::optional<double>> values;
        for (std::size_t v : members) {
          const auto means = tallies[v].image[static_cast<std::size_t>(c)].means();
          if (means) values.push_back((*means)[static_cast<std::size_t>(m)]);
        }
        entry[keys[c]] = number(meanOf(values));
        anyImage = anyImage || !entry[keys[c]].is_null();
      }
      imageGroup[kImageMetrics[m]] = entry;
      imageRows.push_back({"image", groupName, kImageMetrics[m], text(entry["ours"]), "", text(entry["floor_black"]),
                                 text(entry["floor_input"]), viewList, resolution, units});
    }
    if (anyImage) {
      summary.image[groupName] = imageGroup;
      summary.csvRows.insert(summary.csvRows.end(), imageRows.begin(), imageRows.end());
    }
    json temporalGroup = {{"views", names}};
    for (int m = 0; m < 4; ++m) {
      json entry;
      for (const char* key : {"ours", "reference", "floor_black", "floor_input"}) {
        std::vector<std::optional<double>> values;
        for (std::size_t v : members) {
          const json& value = temporalPerView[views[v].name][kTemporalMetrics[m]][key];
          if (!value.is_null() && flow) values.push_back(value.get<double>());
        }
        entry[key] = number(meanOf(values));
      }
      temporalGroup[kTemporalMetrics[m]] = entry;
      summary.csvRows.push_back({"temporal", groupName, kTemporalMetrics[m], text(entry["ours"]), text(entry["reference"]),
                                 text(entry["floor_black"]), text(entry["floor_input"]), viewList, resolution,
                                 m == 0 ? units + ", squared" : "pixels per frame"});
    }
    summary.temporal[groupName] = temporalGroup;
  }
  summary.image["per_view"] = imagePerView;
  if (!flow) summary.temporal = {{"not_computed", "this build has no OpenCV (SMOKESVD_OPENCV off or libopencv-dev missing)"}};
  else summary.temporal["per_view"] = temporalPerView;

  const VolumeTally& t = volume;
  auto mean = [](double sum, int n) { return n > 0 ? json(sum / n) : json(nullptr); };
  summary.volume = {
      {"density_rmse", {{"ours", t.truth ? mean(t.densityOurs, t.densityFrames) : json(nullptr)},
                        {"floor_zero", t.truth ? mean(t.densityZero, t.densityFrames) : json(nullptr)},
                        {"frames", t.truth ? t.densityFrames : 0}}},
      {"velocity_rmse", {{"ours", t.truth ? mean(t.velocityOurs, t.velocityFrames) : json(nullptr)},
                         {"floor_zero", t.truth ? mean(t.velocityZero, t.velocityFrames) : json(nullptr)},
                         {"frames", t.truth ? t.velocityFrames : 0}}},
      {"mean_abs_divergence", {{"ours", mean(t.divergenceOurs, t.motionFrames)},
                               {"truth", t.truth ? mean(t.divergenceTruth, t.motionFrames) : json(nullptr)},
                               {"frames", t.motionFrames}}},
      {"mean_gradient_squared", {{"ours", mean(t.gradientOurs, t.motionFrames)},
                                 {"truth", t.truth ? mean(t.gradientTruth, t.motionFrames) : json(nullptr)},
                                 {"frames", t.motionFrames}}}};
  for (const char* metric : {"density_rmse", "velocity_rmse"})
    summary.csvRows.push_back({"volume", "", metric, text(summary.volume[metric]["ours"]), "",
                               text(summary.volume[metric]["floor_zero"]), "", "", "",
                               std::string(metric) == "density_rmse" ? "networks' density units" : "cells per step"});
  for (const char* metric : {"mean_abs_divergence", "mean_gradient_squared"})
    summary.csvRows.push_back({"volume", "", metric, text(summary.volume[metric]["ours"]), text(summary.volume[metric]["truth"]),
                               "", "", "", "", std::string(metric) == "mean_abs_divergence" ? "cells per step per cell" : "(cells per step per cell)^2"});
  return summary;
}

}  // namespace smokesvd::eval
