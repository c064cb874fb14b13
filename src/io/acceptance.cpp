#include "lathectl/io/acceptance.hpp"

#include <limits>

namespace lathectl::io {

AcceptanceLimits::AcceptanceLimits(std::span<const CriterionKey> keys)
    : keys_(keys), limits_(keys.size()), stated_(keys.size(), 0) {
  for (std::size_t i = 0; i < keys.size(); ++i) limits_[i] = keys[i].fallback;
}

std::size_t AcceptanceLimits::index(std::string_view key) const {
  for (std::size_t i = 0; i < keys_.size(); ++i)
    if (keys_[i].key == key) return i;
  return keys_.size();
}

double AcceptanceLimits::limit(std::string_view key) const {
  const std::size_t i = index(key);
  return i < keys_.size() ? limits_[i] : std::numeric_limits<double>::quiet_NaN();
}

bool AcceptanceLimits::stated(std::string_view key) const {
  const std::size_t i = index(key);
  return i < keys_.size() && stated_[i] != 0;
}

void AcceptanceLimits::set_default(std::string_view key, double limit) {
  const std::size_t i = index(key);
  if (i < keys_.size() && stated_[i] == 0) limits_[i] = limit;
}

void read_acceptance(TableReader& root, AcceptanceLimits& limits) {
  root.document("acceptance",
                "what the part must achieve, in your terms; `lathectl run --strict` is decided by "
                "these criteria (with alarms and unfinished parts), not by the seed's model "
                "checks. Absent: the system's defaults");
  auto t = root.table("acceptance");
  if (!t) return;
  for (std::size_t i = 0; i < limits.keys_.size(); ++i) {
    const CriterionKey& k = limits.keys_[i];
    limits.stated_[i] = t->has(k.key) ? 1 : 0;
    t->read({k.key, k.range, k.doc}, limits.limits_[i]);
  }
  t->finish();
}

}  // namespace lathectl::io
