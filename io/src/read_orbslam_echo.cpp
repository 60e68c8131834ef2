// `rostopic echo /ORB_SLAM/Map` dumps of ORB-SLAM (v1): visualization_msgs/Marker messages in ROS's
// YAML-like text, each followed by a `---` line. ORB-SLAM's MapPublisher re-sends the whole map in
// every publication: namespace "MapPoints", id 0 = all map points, id 6 = reference (local) points,
// both type 8 (POINTS). KeyFrames, Graph and Camera markers are LINE_LISTs and are not map points.
#include <optional>
#include <vector>

#include "read_detail.hpp"

namespace hullmap::io::detail {
namespace {

constexpr int kPointsType = 8;       // visualization_msgs::Marker::POINTS
constexpr int kDeleteAction = 2;     // Marker::DELETE
constexpr int kDeleteAllAction = 3;  // Marker::DELETEALL
constexpr int kAllPointsId = 0;
constexpr int kReferencePointsId = 6;

struct Message {
  std::size_t begin = 0;       // byte offset of its first line
  std::size_t end = 0;         // byte offset just past its last line (the `---` excluded)
  std::size_t first_line = 0;  // 1-based line number of its first line
  std::string ns;
  std::optional<int> id;
  std::optional<int> type;
  int action = 0;
  bool has_header = false;
  bool has_last_field = false;  // `mesh_use_embedded_materials:`, the last field of a Marker
};

std::string_view valueOf(std::string_view line, std::string_view key) {
  std::string_view v = trim(line.substr(key.size()));
  if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'') && v.back() == v.front()) {
    v = v.substr(1, v.size() - 2);
  }
  return v;
}

int intValue(std::string_view line, std::string_view key, const std::string& name, std::size_t line_no) {
  const std::string_view v = valueOf(line, key);
  int value = 0;
  const auto [ptr, ec] = std::from_chars(v.data(), v.data() + v.size(), value);
  if (ec != std::errc() || ptr != v.data() + v.size()) {
    failAt(name, line_no, "'" + std::string(key.substr(0, key.size() - 1)) + "' is not an integer: " + quoted(v));
  }
  return value;
}

bool startsWith(std::string_view s, std::string_view prefix) {
  return s.size() >= prefix.size() && s.compare(0, prefix.size(), prefix) == 0;
}

// Reads the `points:` list of one message into `sink`.
void readMarkerPoints(std::string_view bytes, const Message& message, const std::string& name, PointSink& sink,
                      InputStats& stats) {
  ByteSource source(bytes.substr(message.begin, message.end - message.begin));
  LineCursor cursor(source);
  const auto lineNo = [&] { return message.first_line + cursor.lineNumber() - 1; };
  std::string_view line;
  bool in_points = false;
  bool open_item = false;
  double xyz[3] = {0, 0, 0};
  bool seen[3] = {false, false, false};
  std::size_t item_line = 0;

  const auto closeItem = [&] {
    if (!open_item) return;
    if (!(seen[0] && seen[1] && seen[2])) {
      failAt(name, item_line, "map point without x, y and z");
    }
    ++stats.read;
    keepOrDrop(Point(xyz[0], xyz[1], xyz[2]), sink, stats);
    open_item = false;
  };
  const auto field = [&](std::string_view text) {
    const std::size_t colon = text.find(':');
    if (colon == std::string_view::npos) failAt(name, lineNo(), "expected 'key: value', got " + quoted(text));
    const std::string_view key = trim(text.substr(0, colon));
    const int axis = key == "x" ? 0 : key == "y" ? 1 : key == "z" ? 2 : -1;
    if (axis < 0) return;
    if (!open_item) failAt(name, lineNo(), "point coordinate outside a '-' list item");
    const std::string_view value = trim(text.substr(colon + 1));
    if (!parseDouble(value, xyz[axis])) failAt(name, lineNo(), quoted(value) + " is not a number");
    seen[axis] = true;
  };

  while (cursor.next(line)) {
    const bool top_level = !line.empty() && !isSpace(line.front());
    if (top_level) {
      if (in_points) break;
      if (startsWith(line, "points:")) {
        const std::string_view rest = trim(line.substr(7));
        if (rest == "[]") return;
        if (!rest.empty()) failAt(name, lineNo(), "expected a list after 'points:', got " + quoted(rest));
        in_points = true;
      }
      continue;
    }
    if (!in_points) continue;
    std::string_view t = trim(line);
    if (t.empty()) continue;
    if (t.front() == '-') {
      closeItem();
      open_item = true;
      item_line = lineNo();
      seen[0] = seen[1] = seen[2] = false;
      t = trim(t.substr(1));
      if (t.empty()) continue;
    }
    field(t);
  }
  closeItem();
}

}  // namespace

void parseOrbSlamEcho(ByteSource& input, const std::string& name, PointSink& sink, InputStats& stats) {
  input.loadAll();
  const std::string_view bytes = input.view(0, input.end());
  std::vector<Message> messages;
  // Over a view of the loaded bytes: the messages are visited twice, nothing is released.
  ByteSource source(bytes);
  LineCursor cursor(source);
  std::string_view line;
  Message current;
  current.first_line = 1;
  bool empty = true;
  std::size_t line_start = 0;
  while (cursor.next(line)) {
    const std::size_t line_no = cursor.lineNumber();
    if (line == "---") {
      if (!empty) {
        current.end = line_start;
        messages.push_back(current);
      }
      current = Message();
      current.begin = cursor.offset();
      current.first_line = line_no + 1;
      empty = true;
    } else if (!line.empty() && !isSpace(line.front())) {
      empty = false;
      if (startsWith(line, "header:"))
        current.has_header = true;
      else if (startsWith(line, "ns:"))
        current.ns = std::string(valueOf(line, "ns:"));
      else if (startsWith(line, "id:"))
        current.id = intValue(line, "id:", name, line_no);
      else if (startsWith(line, "type:"))
        current.type = intValue(line, "type:", name, line_no);
      else if (startsWith(line, "action:"))
        current.action = intValue(line, "action:", name, line_no);
      else if (startsWith(line, "mesh_use_embedded_materials:"))
        current.has_last_field = true;
    } else if (!trim(line).empty()) {
      empty = false;
    }
    line_start = cursor.offset();
  }
  // A last message without its `---` is complete only if its last field arrived; otherwise the
  // dump was cut off mid-message and the message is ignored.
  if (!empty && current.has_last_field) {
    current.end = bytes.size();
    messages.push_back(current);
  }

  std::optional<std::size_t> latest[2];  // index into messages for id 0 and id 6
  for (std::size_t i = 0; i < messages.size(); ++i) {
    const Message& m = messages[i];
    if (!m.has_header || !m.id || !m.type) {
      failAt(name, m.first_line, "not a visualization_msgs/Marker message (needs header, ns, id and type fields)");
    }
    if (m.ns != "MapPoints") continue;
    if (m.action == kDeleteAllAction) {
      latest[0].reset();
      latest[1].reset();
      continue;
    }
    const int slot = *m.id == kAllPointsId ? 0 : *m.id == kReferencePointsId ? 1 : -1;
    if (slot < 0) continue;
    if (m.action == kDeleteAction) {
      latest[slot].reset();
    } else if (*m.type == kPointsType) {
      latest[slot] = i;
    }
  }
  for (const auto& index : latest) {
    if (index) readMarkerPoints(bytes, messages[*index], name, sink, stats);
  }
}

}  // namespace hullmap::io::detail
