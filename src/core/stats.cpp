// Stats helpers.

#include "hsr/render.hpp"

namespace hsr {

void Stats::addStage(std::string name, double ms) {
  for (StageTime& s : stages) {
    if (s.name == name) {
      s.ms += ms;
      return;
    }
  }
  stages.push_back({std::move(name), ms});
}

double Stats::totalMs() const {
  double t = 0.0;
  for (const StageTime& s : stages) t += s.ms;
  return t;
}

}  // namespace hsr
