// The CPUs this process may use: its CPU affinity held to its cgroup's CPU quota. A container
// given two CPUs of a 64-core host (docker --cpus=2, a Kubernetes CPU limit) keeps all 64 in its
// affinity, and TBB's default count (oneTBB 2021.8) is the affinity's: a run took 64 threads
// that the quota lets run for 2 CPUs' time, each thread stalled most of every period.
#pragma once

#include <string>

namespace shellcontract {

/// The CPU quota of a process whose /proc/self/cgroup reads `proc_self_cgroup`, the cgroup file
/// systems being mounted at `cgroup_root` ("/sys/fs/cgroup"): ceil(quota / period) of the
/// tightest quota on its cgroup or any ancestor, cgroup v2 (`cpu.max`, "200000 100000") and v1
/// (`cpu.cfs_quota_us`, `cpu.cfs_period_us` of the hierarchy with the cpu controller) alike.
/// 0 when none is set ("max", -1) or none can be read: a missing, unreadable or malformed file
/// is no quota, never an error. Where the cgroup's own folder is not under `cgroup_root` (a
/// container that sees its cgroup's path but has its cgroup mounted as the root), the nearest
/// ancestor that is, down to the root itself, is read.
int cgroup_cpu_limit(const std::string& cgroup_root, const std::string& proc_self_cgroup);

/// The CPUs this process may use: TBB's default concurrency (the CPU affinity: taskset, a
/// cpuset) held to cgroup_cpu_limit of /sys/fs/cgroup and /proc/self/cgroup; at least 1. Read
/// once per process.
int usable_cpus();

}  // namespace shellcontract
