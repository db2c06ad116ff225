// The text of a CSV table, shared by its readers (load profiles, route tables): fields
// separated by commas, or by semicolons (then a decimal comma is read too) or tabs, as
// the header row uses; each field with its 1-based column in the line for errors.
#pragma once
#include <istream>
#include <string>
#include <vector>

namespace packsim::csv {

struct Cell {
  std::string text;
  int column = 1;  // 1-based character position in the line
};

std::string trim(const std::string& s);
std::string unquote(const std::string& s);
// The separator the header row uses: ';' or tab if present, else ','.
char separatorOf(const std::string& header);
std::vector<Cell> splitRow(const std::string& line, char sep);
// Text as read, with what a terminal would not show escaped (\xHH).
std::string visible(const std::string& text);
// 'a', 'b', 'c'
std::string joined(const std::vector<std::string>& names);
// A UTF-8 byte-order mark, as Excel's "CSV UTF-8" starts the file.
constexpr char kUtf8Bom[] = "\xEF\xBB\xBF";
// The next line with content into `line` (its CR line end and the first line's byte-order
// mark removed), skipping blank and '#' comment lines; `lineNo` counts every line read.
// False at the end of the input.
bool nextDataLine(std::istream& in, std::string& line, int& lineNo);

}  // namespace packsim::csv
