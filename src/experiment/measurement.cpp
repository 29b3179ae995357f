// The statistics of a row's repetitions: rates per repetition and their median and spread.
#include "experiment/measurement.hpp"

#include <algorithm>

namespace heightmarch {

std::vector<double> Measurement::rays_per_second() const {
  std::vector<double> rates;
  for (double s : seconds) rates.push_back(s > 0 ? double(rays) / s : 0.0);
  return rates;
}

std::vector<double> Measurement::samples_per_second() const {
  std::vector<double> rates;
  for (double s : seconds) rates.push_back(s > 0 ? double(samples) / s : 0.0);
  return rates;
}

Spread spread_of(std::vector<double> values) {
  if (values.empty()) return {};
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  const double median = n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
  return {median, values.front(), values.back()};
}

}  // namespace heightmarch
