// How much memory a filter run needs and how much this process may still take, so that a mesh too
// large for the machine (or for a `ulimit -v`) is refused with a message before anything is
// allocated, instead of the process being aborted by an uncaught std::bad_alloc or killed by the
// kernel's out-of-memory killer (which an overcommitting Linux does long before malloc fails).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>

#ifdef __linux__
#include <sys/resource.h>
#endif

namespace saliency_bezier {

// What a run needs beyond the mesh MeshLab already holds, in bytes per vertex and per face,
// measured (bench/PERFORMANCE.md "Scale": peak resident set minus the set before the filter, on
// the 2.2M-vertex bunny through meshlabserver and smooth_mesh) with a margin of about 15 %. The
// smoothing filter's peak is its normal filter or patch fits (face rings, weights per face-ring
// entry, face normals in single precision), the analysis filter's the curvature and saliency.
struct MemoryCost {
  double per_vertex = 0, per_face = 0;
  double fixed = 64e6; // thread stacks and malloc arenas of the OpenMP threads, small tables
  double bytes(double vertices, double faces) const {
    return fixed + per_vertex * vertices + per_face * faces;
  }
};
inline MemoryCost smoothingMemoryCost() { return {150, 240}; }
inline MemoryCost analysisMemoryCost() { return {400, 60}; }

// The room is multiplied by this before a run's need is compared with it: 1; the tests set
// infinity to reach the out-of-memory path behind the early refusal.
inline double memory_room_scale = 1.0;

// How much more this process may allocate, and which limit says so.
struct MemoryRoom {
  double bytes = std::numeric_limits<double>::infinity();
  std::string limit; // empty: no limit known
};

namespace detail {

// A "Name:   123 kB" field of a /proc file, in bytes (NaN when absent).
inline double procField(const char *path, const std::string &name) {
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line))
    if (line.compare(0, name.size() + 1, name + ":") == 0) {
      std::istringstream fields(line.substr(name.size() + 1));
      double value = NAN;
      std::string unit;
      fields >> value >> unit;
      return unit == "kB" ? value * 1024 : value;
    }
  return NAN;
}

inline double readNumber(const std::string &path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text == "max") return NAN;
  return std::strtod(text.c_str(), nullptr);
}

} // namespace detail

// The smallest of: the address-space limit (ulimit -v) minus what the process maps, the memory
// the kernel reports available plus free swap, and the room left in the process's cgroup (a
// container's or a systemd slice's memory.max). Linux only; elsewhere no limit is known.
inline MemoryRoom memoryRoom() {
  MemoryRoom room;
#ifdef __linux__
  auto consider = [&](double bytes, const char *limit) {
    if (std::isfinite(bytes) && bytes < room.bytes) room.bytes = std::max(0.0, bytes), room.limit = limit;
  };
  rlimit address_space;
  if (getrlimit(RLIMIT_AS, &address_space) == 0 && address_space.rlim_cur != RLIM_INFINITY)
    consider(double(address_space.rlim_cur) - detail::procField("/proc/self/status", "VmSize"),
             "the process's address-space limit (ulimit -v)");
  consider(detail::procField("/proc/meminfo", "MemAvailable") +
               detail::procField("/proc/meminfo", "SwapFree"),
           "the memory available on this machine");
  // cgroup v2: "0::/path" in /proc/self/cgroup.
  std::ifstream cgroup("/proc/self/cgroup");
  std::string line;
  while (std::getline(cgroup, line))
    if (line.compare(0, 3, "0::") == 0) {
      const std::string dir = "/sys/fs/cgroup" + line.substr(3);
      consider(detail::readNumber(dir + "/memory.max") - detail::readNumber(dir + "/memory.current"),
               "the memory limit of this process's control group");
    }
#endif
  return room;
}

// "1.4 GB", "320 MB".
inline std::string memoryText(double bytes) {
  char text[32];
  if (bytes >= 1e9) std::snprintf(text, sizeof text, "%.1f GB", bytes / 1e9);
  else std::snprintf(text, sizeof text, "%.0f MB", std::ceil(bytes / 1e6));
  return text;
}

} // namespace saliency_bezier
