#include "location.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

#include "traverse/core/comm.hpp"
#include "traverse/output/output_error.hpp"

namespace traverse::output::detail {

namespace fs = std::filesystem;

void agree(MPI_Comm comm, bool ok, const std::string& message) {
  const int rank = par::rank(comm), size = par::size(comm);
  const int failing = ok ? size : rank;
  int first_failing = size;
  par::allreduce(&failing, &first_failing, 1, MPI_INT, MPI_MIN, comm);
  if (first_failing == size) return;
  std::string text = rank == first_failing ? message : std::string();
  unsigned long len = text.size();
  par::bcast(&len, 1, MPI_UNSIGNED_LONG, first_failing, comm);
  text.resize(len);
  par::bcast(text.data(), static_cast<int>(len), MPI_CHAR, first_failing, comm);
  throw OutputError(text);
}

std::string check_location(const std::string& path, const std::string& xmf, bool overwrite) {
  const fs::path p(path);
  if (p.filename().empty()) return "output path '" + path + "' names a folder, not a file";
  const fs::path parent = p.parent_path().empty() ? fs::path(".") : p.parent_path();
  struct stat st {};
  if (stat(parent.c_str(), &st) != 0) {
    if (errno == ENOTDIR)
      return "output folder '" + parent.string() + "' of '" + path +
             "' is not a folder (a path component is a file)";
    return "output folder '" + parent.string() + "' of '" + path +
           "' does not exist: " + std::strerror(errno);
  }
  if (!S_ISDIR(st.st_mode))
    return "output folder '" + parent.string() + "' of '" + path + "' is not a folder";
  if (access(parent.c_str(), W_OK | X_OK) != 0)
    return "output folder '" + parent.string() + "' is not writable: " + std::strerror(errno);
  for (const std::string& f : {path, xmf}) {
    if (f.empty()) continue;
    if (stat(f.c_str(), &st) == 0) {
      if (S_ISDIR(st.st_mode)) return "output path '" + f + "' is an existing folder";
      if (!overwrite)
        return "output file '" + f +
               "' already exists; refusing to overwrite it (pass --overwrite to replace it, "
               "or choose another output path)";
      if (access(f.c_str(), W_OK) != 0)
        return "output file '" + f + "' exists and is not writable: " + std::strerror(errno);
    }
  }
  return {};
}

}  // namespace traverse::output::detail
