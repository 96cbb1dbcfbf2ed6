// The machine's memory, so that a request that cannot fit is refused with an error up front
// instead of the kernel killing the process mid-run.
#pragma once

#include <string>

namespace rayscout {

/// Physical memory plus swap in bytes; 0 when the system does not tell.
double machine_memory_bytes();

/// Throws InputError "<what> need(s) at least N GB, more than this machine's M GB of memory
/// and swap" when need_bytes exceeds machine_memory_bytes() (nothing when that is unknown).
void require_memory(double need_bytes, const std::string& what);

}  // namespace rayscout
