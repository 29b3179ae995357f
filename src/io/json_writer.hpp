#pragma once
// A small JSON writer for metrics and reports: objects and arrays of numbers and strings; numbers in
// their shortest form (append_number, which the CSV files use too).
#include <charconv>
#include <cmath>
#include <cstdio>
#include <string>

#include "heightmarch/error.hpp"

namespace heightmarch {

// The shortest text that reads back as the same number: 0.1f as "0.1", not "0.100000001". A
// double that is exactly a float (the uv error percentiles, scales, angles, ray coordinates: float
// values carried in doubles) is written as that float. For JSON and the CSV files alike.
inline void append_number(std::string& out, double number) {
  char buf[32];
  const float narrow = float(number);
  const auto end = double(narrow) == number ? std::to_chars(buf, buf + sizeof buf, narrow).ptr
                                            : std::to_chars(buf, buf + sizeof buf, number).ptr;
  out.append(buf, end);
}

class JsonWriter {
 public:
  JsonWriter& begin_object(const std::string& key = "") { return open(key, '{'); }
  JsonWriter& end_object() { return close('}'); }
  JsonWriter& begin_array(const std::string& key = "") { return open(key, '['); }
  JsonWriter& end_array() { return close(']'); }

  JsonWriter& value(const std::string& key, const std::string& text) {
    prefix(key);
    out_ += quote(text);
    return *this;
  }
  JsonWriter& value(const std::string& key, const char* text) { return value(key, std::string(text)); }
  JsonWriter& null(const std::string& key) {
    prefix(key);
    out_ += "null";
    return *this;
  }
  JsonWriter& value(const std::string& key, bool b) {
    prefix(key);
    out_ += b ? "true" : "false";
    return *this;
  }
  // NaN and infinities, which JSON lacks, as null; other numbers as append_number writes them.
  JsonWriter& value(const std::string& key, double number) {
    prefix(key);
    if (std::isfinite(number))
      append_number(out_, number);
    else
      out_ += "null";
    return *this;
  }
  JsonWriter& value(const std::string& key, long long number) {
    prefix(key);
    out_ += std::to_string(number);
    return *this;
  }
  JsonWriter& value(const std::string& key, int number) { return value(key, (long long)number); }
  JsonWriter& value(const std::string& key, std::size_t number) { return value(key, (long long)number); }

  // A value another writer wrote (a whole document, trailing newline dropped), indented to fit.
  JsonWriter& raw(const std::string& key, const std::string& json) {
    prefix(key);
    const std::string indent = "\n" + std::string(2 * depth_, ' ');
    const std::size_t end = json.find_last_not_of('\n') + 1;  // npos + 1 == 0 for "" or all newlines
    for (std::size_t i = 0; i < end; ++i) json[i] == '\n' ? out_ += indent : out_ += json[i];
    return *this;
  }

  const std::string& str() const { return out_; }

  // A JSON string, valid UTF-8 whatever bytes text holds (a map's file name may hold any): what a
  // terminal acts on (controls, C1 controls, bidirectional overrides: printable()'s rule) as \u
  // escapes, which read back as the same text; a byte of no UTF-8 character as the text \xNN, as
  // printable() shows it (JSON has no way to carry the byte).
  static std::string quote(const std::string& text) {
    std::string q = "\"";
    for (std::size_t at = 0; at < text.size();) {
      const TextCharacter c = character_at(text, at);
      char buf[16];
      if (c.code == '"' || c.code == '\\') {
        q += '\\';
        q += char(c.code);
      } else if (c.printable) {
        q.append(text, at, c.length);
      } else if (c.code >= 0) {  // all of them in the Basic Multilingual Plane: one \u escape each
        std::snprintf(buf, sizeof buf, "\\u%04x", static_cast<unsigned>(c.code));
        q += buf;
      } else {
        std::snprintf(buf, sizeof buf, "\\\\x%02x", static_cast<unsigned char>(text[at]));
        q += buf;
      }
      at += c.length;
    }
    return q + "\"";
  }

 private:
  JsonWriter& open(const std::string& key, char bracket) {
    prefix(key);
    out_ += bracket;
    first_ = true;
    ++depth_;
    return *this;
  }
  JsonWriter& close(char bracket) {
    --depth_;
    out_ += '\n' + std::string(2 * depth_, ' ') + bracket;
    first_ = false;
    return *this;
  }
  void prefix(const std::string& key) {
    if (depth_ > 0) {
      out_ += first_ ? "\n" : ",\n";
      out_ += std::string(2 * depth_, ' ');
    }
    first_ = false;
    if (!key.empty()) out_ += quote(key) + ": ";
  }

  std::string out_;
  int depth_ = 0;
  bool first_ = true;
};

}  // namespace heightmarch
