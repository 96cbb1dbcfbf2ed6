// The machine's memory: see machine_memory.h.
#include "rayscout/core/machine_memory.h"

#include <sys/sysinfo.h>

#include <cstdio>

#include "rayscout/core/input_error.h"

namespace rayscout {

double machine_memory_bytes() {
  struct sysinfo si;
  if (sysinfo(&si) != 0) return 0.0;
  return (double(si.totalram) + double(si.totalswap)) * double(si.mem_unit);
}

void require_memory(double need_bytes, const std::string& what) {
  const double have = machine_memory_bytes();
  if (have <= 0.0 || need_bytes <= have) return;
  char numbers[128];
  std::snprintf(numbers, sizeof numbers, " at least %.1f GB, more than this machine's %.1f GB of memory and swap",
                need_bytes * 1e-9, have * 1e-9);
  throw InputError(what + numbers);
}

}  // namespace rayscout
