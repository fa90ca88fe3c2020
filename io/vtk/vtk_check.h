// Private to io/vtk/: an Exodus II or CGNS file opened with its own library before VTK's reader
// sees it (vtk_check.cpp says why). Throw InputError naming the file.
#pragma once

#include <string>

namespace topotet::io::vtk {

void check_exodus(const std::string& path);
void check_cgns(const std::string& path);

// The Exodus library's error printing off (VTK's reader turns it on when it opens a file; again()
// turns it off after that), restored at the end of the scope.
class ExodusQuiet {
 public:
  ExodusQuiet();
  ~ExodusQuiet();
  ExodusQuiet(const ExodusQuiet&) = delete;
  ExodusQuiet& operator=(const ExodusQuiet&) = delete;
  void again();

 private:
  int previous_;
};

}  // namespace topotet::io::vtk
