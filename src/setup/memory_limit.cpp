#include "traverse/setup/memory_limit.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace traverse::setup {

namespace {

// A "Key:   value kB" line of a /proc file, in bytes (negative when absent).
double proc_kb(const std::string& file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key + ":", 0) == 0) {
      std::istringstream is(line.substr(key.size() + 1));
      double v = -1.0;
      is >> v;
      return v >= 0.0 ? v * 1024.0 : -1.0;
    }
  return -1.0;
}

// A file holding one number of bytes ("max" or a huge value: no limit -> negative).
double bytes_in(const std::string& file) {
  std::ifstream in(file);
  std::string word;
  if (!(in >> word) || word == "max") return -1.0;
  char* end = nullptr;
  const double v = std::strtod(word.c_str(), &end);
  return *end == '\0' && v > 0.0 && v < 1e18 ? v : -1.0;
}

// This process's cgroup path for a controller ("" for v2), from /proc/self/cgroup.
std::string cgroup_path(const std::string& controller) {
  std::ifstream in("/proc/self/cgroup");
  std::string line;
  while (std::getline(in, line)) {
    const auto a = line.find(':'), b = line.find(':', a + 1);
    if (a == std::string::npos || b == std::string::npos) continue;
    const std::string names = line.substr(a + 1, b - a - 1);
    if (names == controller) return line.substr(b + 1);
  }
  return "";
}

// Room left under the cgroup memory limit (v2, else v1; the process's own group, else the
// root of the mounted hierarchy), negative when there is none.
double cgroup_room() {
  const std::string v2 = "/sys/fs/cgroup", v1 = "/sys/fs/cgroup/memory";
  struct Candidate {
    std::string dir, limit, usage;
  };
  const std::vector<Candidate> candidates = {
      {v2 + cgroup_path(""), "memory.max", "memory.current"},
      {v2, "memory.max", "memory.current"},
      {v1 + cgroup_path("memory"), "memory.limit_in_bytes", "memory.usage_in_bytes"},
      {v1, "memory.limit_in_bytes", "memory.usage_in_bytes"}};
  for (const auto& c : candidates) {
    const double limit = bytes_in(c.dir + "/" + c.limit);
    if (limit <= 0.0) continue;
    return std::max(0.0, limit - std::max(0.0, bytes_in(c.dir + "/" + c.usage)));
  }
  return -1.0;
}

// The smallest finite soft limit of a resource, negative when unlimited.
double rlimit_bytes(int resource) {
  rlimit r{};
  if (getrlimit(resource, &r) != 0 || r.rlim_cur == RLIM_INFINITY) return -1.0;
  return static_cast<double>(r.rlim_cur);
}

MemoryLimit this_rank(int ranks_on_host) {
  MemoryLimit m;
  double host = proc_kb("/proc/meminfo", "MemAvailable");
  m.source = "MemAvailable of this host";
  const double cg = cgroup_room();
  if (cg >= 0.0 && (host < 0.0 || cg < host)) {
    host = cg;
    m.source = "the room left under this process's cgroup memory limit";
  }
  if (host < 0.0) {
    host = static_cast<double>(sysconf(_SC_AVPHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
    m.source = "the available physical memory of this host";
  }
  m.bytes = host / ranks_on_host;
  if (ranks_on_host > 1) m.source += " shared by the " + std::to_string(ranks_on_host) + " ranks on it";
  // An address-space limit counts mapped but not resident memory too (libraries, MPI
  // segments): what is left of it for resident memory is the limit minus that overhead.
  const double size = proc_kb("/proc/self/status", "VmSize"), rss = proc_kb("/proc/self/status", "VmRSS");
  const double as = rlimit_bytes(RLIMIT_AS);
  if (as > 0.0) {
    const double room = as - std::max(0.0, size - rss);
    if (room < m.bytes) {
      m.bytes = std::max(0.0, room);
      m.source = "the address-space limit of this process (ulimit -v " + format_bytes(as) + ", less " +
                 format_bytes(std::max(0.0, size - rss)) + " mapped but not resident)";
    }
  }
  const double data = rlimit_bytes(RLIMIT_DATA);
  if (data > 0.0 && data < m.bytes) {
    m.bytes = data;
    m.source = "the data-size limit of this process (ulimit -d)";
  }
  return m;
}

}  // namespace

MemoryLimit memory_limit(const RunLimits& limits, MPI_Comm comm) {
  if (limits.max_memory > 0.0)
    return {limits.max_memory,
            limits.memory_source.empty() ? "--max-memory " + format_bytes(limits.max_memory) : limits.memory_source};
  if (comm == MPI_COMM_NULL) return this_rank(1);  // MPI not started
  MPI_Comm host;
  MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &host);
  int on_host = 1;
  MPI_Comm_size(host, &on_host);
  MPI_Comm_free(&host);
  MemoryLimit mine = this_rank(on_host);
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  struct {
    double value;
    int rank;
  } in{mine.bytes, rank}, out{0.0, 0};
  MPI_Allreduce(&in, &out, 1, MPI_DOUBLE_INT, MPI_MINLOC, comm);
  // The source text of the rank with the smallest figure.
  int length = static_cast<int>(mine.source.size());
  MPI_Bcast(&length, 1, MPI_INT, out.rank, comm);
  std::string source(static_cast<std::size_t>(length), ' ');
  if (rank == out.rank) source = mine.source;
  MPI_Bcast(source.data(), length, MPI_CHAR, out.rank, comm);
  return {out.value, source};
}

}  // namespace traverse::setup
