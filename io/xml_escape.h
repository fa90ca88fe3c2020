// XML attribute escaping, shared by the .vtu writer and the MPI .pvtu writer (mpi/).
#pragma once

#include <string>

namespace topotet::io {

inline std::string xml_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace topotet::io
