// How much memory this process may use: the machine's, or less where a container's cgroup
// limits it (what the kernel's OOM killer goes by). The default memory budget is a share of it.
#pragma once

#include <cstdint>

namespace tessera::server {

// The smallest of /proc/meminfo's MemTotal and the cgroup's limit (v2 memory.max, v1
// memory.limit_in_bytes); 0 if none can be read.
int64_t machineMemoryBytes();

}  // namespace tessera::server
