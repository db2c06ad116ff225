#include "core/scenario/csv_text.hpp"

namespace packsim::csv {

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::string unquote(const std::string& s) {
  return s.size() >= 2 && s.front() == '"' && s.back() == '"' ? s.substr(1, s.size() - 2) : s;
}

// The separator the header row uses: ';' or tab if present, else ','.
char separatorOf(const std::string& header) {
  if (header.find(';') != std::string::npos) return ';';
  if (header.find('\t') != std::string::npos && header.find(',') == std::string::npos) return '\t';
  return ',';
}

std::vector<Cell> splitRow(const std::string& line, char sep) {
  std::vector<Cell> cells;
  size_t start = 0;
  while (true) {
    const size_t end = line.find(sep, start);
    const std::string raw = line.substr(start, end == std::string::npos ? std::string::npos : end - start);
    const size_t lead = raw.find_first_not_of(" \t\r");
    cells.push_back({trim(raw), static_cast<int>(start + (lead == std::string::npos ? 0 : lead)) + 1});
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return cells;
}

// Text as read, with what a terminal would not show escaped: control characters and
// bytes outside printable ASCII as \xHH (a byte-order mark is \xEF\xBB\xBF), so two
// names that print alike but differ show the difference.
std::string visible(const std::string& text) {
  static const char* hex = "0123456789ABCDEF";
  std::string out;
  for (const char ch : text) {
    const auto b = static_cast<unsigned char>(ch);
    if (b >= 0x20 && b < 0x7F && b != '\\') {
      out += ch;
    } else {
      out += "\\x";
      out += hex[b >> 4];
      out += hex[b & 0xF];
    }
  }
  return out;
}

std::string joined(const std::vector<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + ("'" + visible(n) + "'");
  return s;
}

bool nextDataLine(std::istream& in, std::string& line, int& lineNo) {
  while (std::getline(in, line)) {
    ++lineNo;
    if (!line.empty() && line.back() == '\r') line.pop_back();  // CRLF line ends
    if (lineNo == 1 && line.compare(0, 3, kUtf8Bom) == 0) line.erase(0, 3);
    const std::string t = trim(line);
    if (!t.empty() && t[0] != '#') return true;
  }
  return false;
}

}  // namespace packsim::csv
