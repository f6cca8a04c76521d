#include "tkgslam/common/ResidentMemory.h"

#include <fstream>

#include <unistd.h>

namespace tkgslam {

double residentMemoryMiB() {
  std::ifstream statm("/proc/self/statm");
  long total_pages = 0, resident_pages = 0;
  if (!(statm >> total_pages >> resident_pages)) return 0.0;
  return static_cast<double>(resident_pages) * static_cast<double>(sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

}  // namespace tkgslam
