#pragma once
// A number as messages show it: the shortest form the standard stream gives ("0.01", "1e+06",
// "nan"), so that an error quotes the value the user wrote.
#include <sstream>
#include <string>

namespace semfuse {

inline std::string numberText(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

}  // namespace semfuse
