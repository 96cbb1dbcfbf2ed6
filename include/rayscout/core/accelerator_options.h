// AcceleratorOptions: named tunables ("key=value") passed to an accelerator's factory.
#pragma once

#include <initializer_list>
#include <map>
#include <set>
#include <span>
#include <string>
#include <utility>

#include "rayscout/core/input_error.h"

namespace rayscout {

/// Key=value tunables, e.g. "skip=off" or "budget_mib=64". Each accelerator reads the keys
/// it knows with a default; keys nobody read are reported by check_all_used(), so a
/// misspelt switch is an error, never silently ignored.
class AcceleratorOptions {
 public:
  AcceleratorOptions() = default;
  /// Parses "key=value"; throws InputError on a missing '='.
  void set(const std::string& key_equals_value);
  void set(const std::string& key, const std::string& value) { values_[key] = value; }
  /// A command line's "key=value" list (--accel-opt): set() for each, but a key given twice is
  /// an InputError, as a repeated command-line option is, instead of the last one winning.
  static AcceleratorOptions from_list(std::span<const std::string> key_equals_values);

  bool get_bool(const std::string& key, bool fallback) const;
  long get_int(const std::string& key, long fallback) const;
  /// get_int, but a value outside [lo, hi] throws InputError naming the key, the value and the
  /// range (so that a narrowing cast after it, e.g. int(...), never wraps a huge value).
  long get_int(const std::string& key, long fallback, long lo, long hi) const;
  /// A finite number (NaN and infinity throw InputError).
  double get_double(const std::string& key, double fallback) const;
  /// get_double, but a value outside [lo, hi] throws InputError naming the key and the range.
  double get_double(const std::string& key, double fallback, double lo, double hi) const;
  std::string get_string(const std::string& key, const std::string& fallback) const;
  /// A named choice, e.g. collapse=greedy|sah: the value paired with the key's value in names
  /// (fallback when the key is absent); any other value throws InputError naming the key, the
  /// value and every choice.
  template <class T>
  T get_choice(const std::string& key, T fallback, std::span<const std::pair<const char*, T>> names) const {
    const auto it = values_.find(key);
    used_.insert(key);
    if (it == values_.end()) return fallback;
    for (const auto& [name, value] : names)
      if (it->second == name) return value;
    std::string list;
    for (size_t i = 0; i < names.size(); ++i)
      list += std::string(i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i].first;
    throw InputError("option '" + key + "': '" + it->second + "' is not " + list);
  }
  template <class T>
  T get_choice(const std::string& key, T fallback, std::initializer_list<std::pair<const char*, T>> names) const {
    return get_choice(key, fallback, std::span(names.begin(), names.size()));
  }
  bool has(const std::string& key) const { return values_.count(key) != 0; }
  /// Throws InputError naming every key that no get_* call asked for.
  void check_all_used(const std::string& accelerator) const;
  /// The same keys and values with none asked for yet: what one accelerator's reading starts
  /// from, so that check_all_used() judges its reads alone.
  AcceleratorOptions unread() const {
    AcceleratorOptions o;
    o.values_ = values_;
    return o;
  }

 private:
  /// "key=value" split at the first '='; throws InputError on a missing '=' or key.
  static std::pair<std::string, std::string> split(const std::string& key_equals_value);

  std::map<std::string, std::string> values_;
  mutable std::set<std::string> used_;
};

}  // namespace rayscout
