// AcceleratorOptions: parsing and typed access.
#include "rayscout/core/accelerator_options.h"

#include <charconv>
#include <cmath>
#include <string>
#include <type_traits>

namespace rayscout {
namespace {

template <typename T>
T parse_number(const std::string& key, const std::string& text) {
  T value{};
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec == std::errc() && ptr == end) return value;
  const std::string said = "option '" + key + "': '" + text + "' ";
  if (ec == std::errc::result_out_of_range && ptr == end) throw InputError(said + "is out of range");
  // Say which rule the text broke: bins=1e9 is a number, just not an integer.
  if constexpr (std::is_integral_v<T>) {
    double d = 0;
    const auto r = std::from_chars(text.data(), end, d);
    if (!text.empty() && r.ptr == end && r.ec != std::errc::invalid_argument) throw InputError(said + "is not an integer");
  }
  throw InputError(said + "is not a number");
}

// The shortest text that reads back as x: 1.0000001 must not print as 1 next to a bound of 1.
std::string shortest(double x) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, end);
}

}  // namespace

std::pair<std::string, std::string> AcceleratorOptions::split(const std::string& key_equals_value) {
  const auto eq = key_equals_value.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError("option '" + key_equals_value + "': expected key=value");
  return {key_equals_value.substr(0, eq), key_equals_value.substr(eq + 1)};
}

void AcceleratorOptions::set(const std::string& key_equals_value) {
  auto [key, value] = split(key_equals_value);
  values_[std::move(key)] = std::move(value);
}

AcceleratorOptions AcceleratorOptions::from_list(std::span<const std::string> key_equals_values) {
  AcceleratorOptions options;
  for (const std::string& kv : key_equals_values) {
    auto [key, value] = split(kv);
    if (const auto it = options.values_.find(key); it != options.values_.end())
      throw InputError("option '" + key + "' given twice ('" + it->second + "' and '" + value + "')");
    options.values_.emplace(std::move(key), std::move(value));
  }
  return options;
}

bool AcceleratorOptions::get_bool(const std::string& key, bool fallback) const {
  auto it = values_.find(key);
  used_.insert(key);
  if (it == values_.end()) return fallback;
  const std::string& v = it->second;
  if (v == "1" || v == "on" || v == "true" || v == "yes") return true;
  if (v == "0" || v == "off" || v == "false" || v == "no") return false;
  throw InputError("option '" + key + "': '" + v + "' is not on/off");
}

long AcceleratorOptions::get_int(const std::string& key, long fallback) const {
  auto it = values_.find(key);
  used_.insert(key);
  return it == values_.end() ? fallback : parse_number<long>(key, it->second);
}

long AcceleratorOptions::get_int(const std::string& key, long fallback, long lo, long hi) const {
  const long value = get_int(key, fallback);
  if (value < lo || value > hi)
    throw InputError("option '" + key + "': " + std::to_string(value) + " is not in [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "]");
  return value;
}

double AcceleratorOptions::get_double(const std::string& key, double fallback) const {
  auto it = values_.find(key);
  used_.insert(key);
  if (it == values_.end()) return fallback;
  const double value = parse_number<double>(key, it->second);  // from_chars also reads "nan", "inf"
  if (!std::isfinite(value)) throw InputError("option '" + key + "': '" + it->second + "' is not a finite number");
  return value;
}

double AcceleratorOptions::get_double(const std::string& key, double fallback, double lo, double hi) const {
  const double value = get_double(key, fallback);
  if (value < lo || value > hi)
    throw InputError("option '" + key + "': " + shortest(value) + " is not in [" + shortest(lo) + ", " + shortest(hi) +
                     "]");
  return value;
}

std::string AcceleratorOptions::get_string(const std::string& key, const std::string& fallback) const {
  auto it = values_.find(key);
  used_.insert(key);
  return it == values_.end() ? fallback : it->second;
}

void AcceleratorOptions::check_all_used(const std::string& accelerator) const {
  std::string unknown;
  for (const auto& [key, value] : values_)
    if (!used_.count(key)) unknown += (unknown.empty() ? "" : ", ") + key;
  if (unknown.empty()) return;
  // The keys the accelerator asked for are its options: naming them spares a trip to its doc.
  std::string known;
  for (const std::string& key : used_)
    known += (known.empty() ? "" : ", ") + key;
  throw InputError("accelerator '" + accelerator + "' has no option(s): " + unknown +
                   (known.empty() ? " (it has no options)" : " (its options: " + known + ")"));
}

}  // namespace rayscout
