// The run summary's text is a table of lines (summary_text.cpp, vehicle_text.cpp): each
// row a label, the /summary figures it prints (summary_fields.cpp names) and how it
// writes its line or lines. LineWriter pads the label to the summary's 16 columns.
#pragma once
#include <string>

namespace packsim {

class LineWriter {
 public:
  explicit LineWriter(std::string& out) : out_(out) {}
  // The row whose lines follow.
  void row(const char* label) { label_ = label; }
  // A line under the row's label.
  void line(const std::string& body) { line(label_, body); }
  // A line under a label of its own (a row whose lines differ in label).
  void line(const char* label, const std::string& body) {
    std::string l = label;
    l.resize(kLabelColumns, ' ');
    out_ += l + body + "\n";
  }
  // A line continuing the one above it: no label.
  void more(const std::string& body) { line("", body); }

  static constexpr size_t kLabelColumns = 16;

 private:
  std::string& out_;
  const char* label_ = "";
};

}  // namespace packsim
