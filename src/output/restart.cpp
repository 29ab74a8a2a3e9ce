#include "traverse/output/restart.hpp"

#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <set>


#include "traverse/core/comm.hpp"

namespace traverse::output {

namespace fs = std::filesystem;

namespace {

constexpr double kFormat = 1.0;
constexpr std::size_t kMetaFixed = 6;  // format, time, step, steps_written, checksum hi, lo
const char* const kSlot[2] = {"a", "b"};

std::uint64_t fnv1a(std::uint64_t h, const void* data, std::size_t bytes) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= 1099511628211ULL;
  }
  return h;
}
constexpr std::uint64_t kFnvBasis = 14695981039346656037ULL;

// Sum over nodes of the hash of (global index, values): independent of the rank split.
std::uint64_t nodes_checksum(const double* values, std::size_t count, std::size_t components, std::size_t first) {
  std::uint64_t sum = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint64_t j = first + k;
    std::uint64_t h = fnv1a(kFnvBasis, &j, sizeof j);
    h = fnv1a(h, values + k * components, components * sizeof(double));
    sum += h;
  }
  return sum;
}

std::uint64_t meta_checksum(const std::vector<double>& meta) {
  std::uint64_t h = kFnvBasis;
  for (std::size_t i = 0; i < meta.size(); ++i)
    if (i != 4 && i != 5) h = fnv1a(h, &meta[i], sizeof(double));
  return h;
}

std::string before_restart(const std::string& path) { return path + ".before-restart"; }

}  // namespace

std::string restart_source(const std::string& path) {
  std::error_code ec;
  return fs::exists(before_restart(path), ec) ? before_restart(path) : path;
}

std::string move_aside_for_restart(const std::string& path, MPI_Comm comm) {
  const int rank = par::rank(comm);
  const std::string backup = before_restart(path);
  // Every rank has finished reading the file (scene, restart point, outputs) before rank 0
  // renames it: a rank still opening `path` would otherwise fail alone and deadlock the rest.
  par::barrier(comm);
  int ok = 1;
  std::string err;
  if (rank == 0) {
    std::error_code ec;
    if (!fs::exists(backup, ec)) {
      fs::rename(path, backup, ec);
      if (ec) {
        ok = 0;
        err = "--restart " + path + ": cannot rename it to " + backup + " (" + ec.message() + ")";
      }
    }
  }
  par::bcast(&ok, 1, MPI_INT, 0, comm);
  if (!ok) throw RestartError(rank == 0 ? err : "--restart " + path + ": cannot move it aside");
  return backup;
}

void remove_restart_source(const std::string& path, MPI_Comm comm) {
  const int rank = par::rank(comm);
  par::barrier(comm);
  if (rank == 0) {
    std::error_code ec;
    fs::remove(before_restart(path), ec);
  }
  par::barrier(comm);
}

void set_file_status(const std::string& path, const std::string& status, MPI_Comm comm) {
  if (path.empty()) return;
  const int rank = par::rank(comm);
  par::barrier(comm);
  if (rank == 0) {
    H5E_auto2_t old_func = nullptr;
    void* old_data = nullptr;
    H5Eget_auto2(H5E_DEFAULT, &old_func, &old_data);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    bool done = false;
    const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    if (fapl >= 0) H5Pset_file_locking(fapl, 0, 1);
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl >= 0 ? fapl : H5P_DEFAULT);
    if (f >= 0) {
      const hid_t t = H5Tcopy(H5T_C_S1);
      H5Tset_size(t, H5T_VARIABLE);
      H5Tset_cset(t, H5T_CSET_UTF8);
      hid_t a = H5Aopen(f, "status", H5P_DEFAULT);
      if (a < 0) {
        const hid_t sp = H5Screate(H5S_SCALAR);
        a = H5Acreate2(f, "status", t, sp, H5P_DEFAULT, H5P_DEFAULT);
        H5Sclose(sp);
      }
      if (a >= 0) {
        const char* p = status.c_str();
        done = H5Awrite(a, t, &p) >= 0;
        H5Aclose(a);
      }
      H5Tclose(t);
      done = H5Fclose(f) >= 0 && done;
    }
    if (fapl >= 0) H5Pclose(fapl);
    H5Eset_auto2(H5E_DEFAULT, old_func, old_data);
    if (!done) std::cerr << "traverse: could not set the status of " << path << " to '" << status << "'\n";
  }
  par::barrier(comm);
}

RestartSlots::RestartSlots(MPI_Comm comm, std::size_t components, std::size_t first_node)
    : comm_(comm), components_(components), first_(first_node) {}

void RestartSlots::write(Writer& writer, double time, long step, const std::vector<double>& extra,
                         const std::vector<double>& local) {
  const int slot = current_ < 0 ? 0 : 1 - current_;
  std::vector<double> meta(kMetaFixed, 0.0);
  meta[0] = kFormat;
  meta[1] = time;
  meta[2] = static_cast<double>(step);
  meta[3] = static_cast<double>(writer.steps_written());
  meta.insert(meta.end(), extra.begin(), extra.end());
  std::uint64_t mine = nodes_checksum(local.data(), local.size() / components_, components_, first_), sum = 0;
  par::allreduce(&mine, &sum, 1, MPI_UINT64_T, MPI_SUM, comm_);
  const std::uint64_t c = sum + meta_checksum(meta);
  meta[4] = static_cast<double>(c >> 32);
  meta[5] = static_cast<double>(c & 0xffffffffULL);
  state_[slot] = local;
  meta_[slot] = std::move(meta);
  std::vector<RestartArray> arrays;
  for (int s = 0; s < 2; ++s) {
    if (meta_[s].empty()) continue;
    arrays.push_back({std::string(kSlot[s]) + ".state", RestartDistribution::per_node, components_,
                      DoubleView(state_[s])});
    arrays.push_back({std::string(kSlot[s]) + ".meta", RestartDistribution::replicated, 1,
                      DoubleView(meta_[s])});
  }
  writer.write_restart(time, arrays);
  current_ = slot;
}

RestartPoint read_restart_point(const std::string& source, std::size_t nodes, std::size_t components) {
  RestartPoint best;
  bool found = false;
  std::string why = "no restart point stored";
  try {
    Reader r(source);
    const std::size_t file_steps = r.steps_written();
    const auto names = r.restart_names();
    for (const char* slot : kSlot) {
      const std::string s(slot);
      if (std::find(names.begin(), names.end(), s + ".meta") == names.end() ||
          std::find(names.begin(), names.end(), s + ".state") == names.end())
        continue;
      Series meta, state;
      try {
        meta = r.restart(s + ".meta");
        state = r.restart(s + ".state");
      } catch (const OutputError& e) {  // a kill -9 inside its write can leave a slot unreadable
        why = "restart slot " + s + " cannot be read (" + e.what() + ")";
        continue;
      }
      if (meta.values.size() < kMetaFixed || meta.values[0] != kFormat) {
        why = "restart slot " + s + " has an unknown format";
        continue;
      }
      if (state.rows != nodes || state.components != components) {
        why = "restart slot " + s + " holds " + std::to_string(state.rows) + " x " +
              std::to_string(state.components) + " values, the scene needs " + std::to_string(nodes) + " x " +
              std::to_string(components) + " (a different mesh or model?)";
        continue;
      }
      const std::uint64_t c = nodes_checksum(state.values.data(), nodes, components, 0) + meta_checksum(meta.values);
      if (static_cast<double>(c >> 32) != meta.values[4] || static_cast<double>(c & 0xffffffffULL) != meta.values[5]) {
        why = "restart slot " + s + " fails its checksum (the run was killed while writing it)";
        continue;
      }
      const auto written = static_cast<std::size_t>(meta.values[3]);
      if (written > file_steps || written == 0) {
        why = "restart slot " + s + " refers to output step " + std::to_string(written) + " beyond the file's " +
              std::to_string(file_steps);
        continue;
      }
      if (found && written <= best.steps_written) continue;
      found = true;
      best.time = meta.values[1];
      best.step = static_cast<long>(meta.values[2]);
      best.steps_written = written;
      best.extra.assign(meta.values.begin() + kMetaFixed, meta.values.end());
      best.state = state.values;
      best.components = components;
      best.slot = s;
    }
  } catch (const OutputError& e) {
    throw RestartError("--restart: cannot read the restart point of " + source + " (" + e.what() + ")");
  }
  if (!found) throw RestartError("--restart: " + source + " has no usable restart point: " + why);
  return best;
}

void check_restart_outputs(const std::string& source, const std::vector<std::string>& probe_names,
                           const std::vector<std::string>& field_names) {
  try {
    Reader r(source);
    const auto have_p = r.probe_names();
    const auto have_f = r.field_names();
    const std::set<std::string> hp(have_p.begin(), have_p.end()), wp(probe_names.begin(), probe_names.end());
    const std::set<std::string> hf(have_f.begin(), have_f.end()), wf(field_names.begin(), field_names.end());
    auto join = [](const std::set<std::string>& s) {
      std::string out;
      for (const auto& x : s) out += (out.empty() ? "" : ", ") + x;
      return "[" + out + "]";
    };
    if (hp != wp)
      throw RestartError("--restart: " + source + " has the probes " + join(hp) + ", the scene declares " + join(wp) +
                       " (a restart must keep output.probes and the loads)");
    if (hf != wf)
      throw RestartError("--restart: " + source + " has the fields " + join(hf) + ", the scene declares " + join(wf) +
                       " (a restart must keep output.fields)");
  } catch (const OutputError& e) {
    throw RestartError("--restart: cannot read " + source + " (" + e.what() + ")");
  }
}

void copy_output_steps(const std::string& source, Writer& writer, std::size_t steps,
                       const std::vector<std::string>& probe_names,
                       const std::vector<std::string>& field_names, std::size_t first, std::size_t count) {
  try {
    Reader r(source);
    check_restart_outputs(source, probe_names, field_names);
    if (steps > r.steps_written())
      throw RestartError("--restart: " + source + " has " + std::to_string(r.steps_written()) +
                       " output steps, the restart point needs " + std::to_string(steps));
    const std::vector<double> time = r.time();
    const Series sigma = r.sigma();
    std::vector<Series> probes;
    for (const auto& n : probe_names) probes.push_back(r.probe(n));
    std::vector<double> sig(sigma.components);
    std::vector<std::vector<double>> pv(probes.size());
    std::vector<std::vector<double>> fv(field_names.size());
    for (std::size_t s = 0; s < steps; ++s) {
      std::copy_n(sigma.values.begin() + static_cast<std::ptrdiff_t>(s * sigma.components), sigma.components,
                  sig.begin());
      for (std::size_t p = 0; p < probes.size(); ++p) {
        const std::size_t c = probes[p].components;
        pv[p].assign(probes[p].values.begin() + static_cast<std::ptrdiff_t>(s * c),
                     probes[p].values.begin() + static_cast<std::ptrdiff_t>((s + 1) * c));
      }
      for (std::size_t f = 0; f < field_names.size(); ++f)
        fv[f] = count > 0 ? r.field(field_names[f], s, first, count) : std::vector<double>();
      std::vector<DoubleView> views(fv.begin(), fv.end());
      writer.write_step(time[s], sig, pv, views);
    }
  } catch (const OutputError& e) {
    throw RestartError("--restart: cannot copy the output steps of " + source + " (" + e.what() + ")");
  }
}

}  // namespace traverse::output
