#pragma once
// ParaView data collection (.pvd): the list of time steps of one series of
// .vtu files. Rewritten atomically after every addition, so it always names
// only files that were completely written before it.
#include <string>
#include <vector>

namespace fdem {

class PvdCollection {
 public:
  struct Entry {
    double time_s;
    std::string file;  // relative to the .pvd's folder
  };

  explicit PvdCollection(std::string path) : path_(std::move(path)) {}

  /// Records a dataset (already written) and rewrites the .pvd.
  void add(double time_s, const std::string& file);
  /// Drops entries later than `time_s` (a restart from a checkpoint at that time).
  void truncate_after(double time_s);

  std::string content() const;
  void write() const;
  const std::vector<Entry>& entries() const { return entries_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<Entry> entries_;
};

}  // namespace fdem
