#include "host/driver/fst_signals.hpp"

#include <gtkwave/fstapi.h>

#include "sim/error.hpp"

namespace rheo::driver {

FstContents read_fst_signals(const std::string& path) {
  void* fst = fstReaderOpen(path.c_str());
  if (!fst) throw Error("cannot read FST file " + path);
  FstContents c;
  c.start_time = fstReaderGetStartTime(fst);
  c.end_time = fstReaderGetEndTime(fst);
  c.timescale_exponent = fstReaderGetTimescale(fst);
  std::vector<std::string> scopes;
  fstReaderIterateHierRewind(fst);
  while (const fstHier* h = fstReaderIterateHier(fst)) {
    if (h->htyp == FST_HT_SCOPE) {
      scopes.emplace_back(h->u.scope.name, h->u.scope.name_length);
    } else if (h->htyp == FST_HT_UPSCOPE) {
      if (!scopes.empty()) scopes.pop_back();
    } else if (h->htyp == FST_HT_VAR) {
      // Verilator names a vector "name [msb:lsb]"; GTKWave drops the blank. A vector
      // without a range gets [width-1:0] in GTKWave.
      std::string name(h->u.var.name, h->u.var.name_length);
      const std::size_t blank = name.find(" [");
      if (blank != std::string::npos) name.erase(blank, 1);
      if (h->u.var.length > 1 && name.back() != ']') {
        // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on a + chain here.
        name.append("[").append(std::to_string(h->u.var.length - 1)).append(":0]");
      }
      std::string full;
      for (const std::string& s : scopes) full.append(s).append(".");
      full.append(name);
      c.signals.push_back({full, int(h->u.var.length)});
    }
  }
  fstReaderClose(fst);
  return c;
}

}  // namespace rheo::driver
