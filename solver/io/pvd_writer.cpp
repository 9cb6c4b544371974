#include "io/pvd_writer.hpp"

#include <algorithm>
#include <iterator>

#include <fmt/format.h>

#include "io/atomic_file.hpp"

namespace fdem {

void PvdCollection::add(double time_s, const std::string& file) {
  entries_.push_back({time_s, file});
  write();
}

void PvdCollection::truncate_after(double time_s) {
  std::erase_if(entries_, [&](const Entry& e) { return e.time_s > time_s; });
}

std::string PvdCollection::content() const {
  fmt::memory_buffer out;
  fmt::format_to(std::back_inserter(out),
                 "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
                 "<Collection>\n");
  for (const Entry& e : entries_) {
    fmt::format_to(std::back_inserter(out), "<DataSet timestep=\"{}\" part=\"0\" file=\"{}\"/>\n", e.time_s, e.file);
  }
  fmt::format_to(std::back_inserter(out), "</Collection>\n</VTKFile>\n");
  return fmt::to_string(out);
}

void PvdCollection::write() const { write_file_atomically(path_, content()); }

}  // namespace fdem
