// SPDX-License-Identifier: MIT
/// @file run_replay: request by request, answer, compare byte for byte, explain differences.
#include "replay.hpp"

#include <algorithm>
#include <nlohmann/json.hpp>

namespace cmmcomp::replay {

namespace {

/// One recorded request and the recorded answers that follow it.
struct Step {
  const WireMessage* request = nullptr;
  std::vector<WireMessage> expected;
};

bool same(const WireMessage& a, const WireMessage& b) {
  return a.can_id == b.can_id && a.bytes == b.bytes;
}

std::string bytes_range(const FieldValue& f) {
  return f.end - f.begin == 1
             ? "byte " + std::to_string(f.begin)
             : "bytes " + std::to_string(f.begin) + "-" + std::to_string(f.end - 1);
}

bool same_bytes(const WireMessage& a, const WireMessage& b, const FieldValue& f) {
  if (f.end > a.bytes.size() || f.end > b.bytes.size()) return false;
  return std::equal(a.bytes.begin() + static_cast<long>(f.begin),
                    a.bytes.begin() + static_cast<long>(f.end),
                    b.bytes.begin() + static_cast<long>(f.begin));
}

/// Fills the byte offset, the field and the list of differing fields of `m`.
void explain(const Session& session,
             const WireMessage& request,
             const WireMessage& expected,
             const WireMessage& actual,
             Mismatch& m) {
  if (expected.can_id != actual.can_id) {
    m.field = "CAN identifier " + session.format(expected).substr(0, 3) + " recorded vs " +
              session.format(actual).substr(0, 3) + " replayed";
  } else {
    const std::size_t n = std::min(expected.bytes.size(), actual.bytes.size());
    std::size_t i = 0;
    while (i < n && expected.bytes[i] == actual.bytes[i]) ++i;
    m.byte_offset = static_cast<long>(i);
    if (i == n) {
      m.field = "length: " + std::to_string(expected.bytes.size()) + " bytes recorded vs " +
                std::to_string(actual.bytes.size()) + " replayed";
    }
  }
  const std::vector<FieldValue> fe = session.decode_answer(request, expected);
  const std::vector<FieldValue> fa = session.decode_answer(request, actual);
  if (m.byte_offset >= 0 && m.field.empty()) {
    const FieldValue* f = field_at(fe, static_cast<std::size_t>(m.byte_offset));
    m.field = f != nullptr ? f->name + " (" + bytes_range(*f) + ")" : "no field (outside the map)";
  }
  for (const FieldValue& e : fe) {
    for (const FieldValue& a : fa) {
      if (a.name != e.name || a.begin != e.begin || a.end != e.end) continue;
      if (same_bytes(expected, actual, e)) continue;
      const bool shown_equal = a.value == e.value;
      m.differences.push_back(e.name + " " + (shown_equal ? e.precise : e.value) + " recorded vs " +
                              (shown_equal ? a.precise : a.value) + " replayed");
    }
  }
}

}  // namespace

ReplayResult run_replay(const Recording& recording,
                        Session& session,
                        const ReplayOptions& options,
                        std::ostream* text) {
  ReplayResult r;
  r.source = recording.source;
  r.format = to_string(recording.format);
  r.target = session.target();

  std::vector<Step> steps;
  for (const WireMessage& m : recording.messages) {
    switch (session.classify(m)) {
      case Session::Role::kRequest:
        steps.push_back(Step{&m, {}});
        break;
      case Session::Role::kAnswer:
        if (steps.empty()) {
          ++r.other;  // an answer before any request: nothing to replay it against
        } else {
          steps.back().expected.push_back(m);
        }
        break;
      case Session::Role::kHeartbeat:
        ++r.heartbeats;
        break;
      case Session::Role::kOther:
        ++r.other;
        break;
    }
  }
  const std::int64_t last_time = recording.messages.empty() ? 0 : recording.messages.back().time_us;

  for (std::size_t s = 0; s < steps.size(); ++s) {
    const Step& step = steps[s];
    const std::int64_t next_time = s + 1 < steps.size() ? steps[s + 1].request->time_us : last_time;
    const std::string request_summary = session.describe_request(*step.request);
    const std::vector<WireMessage> actual =
        session.answer(*step.request, next_time, step.expected.size());
    ++r.requests;
    r.answers += step.expected.size();

    bool match = actual.size() == step.expected.size();
    std::size_t first = 0;
    for (; first < std::min(actual.size(), step.expected.size()); ++first) {
      if (!same(actual[first], step.expected[first])) {
        match = false;
        break;
      }
    }
    if (!actual.empty() || !step.expected.empty() || !match) {
      ExchangeLine e{step.request->line,
                     request_summary,
                     session.describe_answers(*step.request, actual),
                     match};
      if (options.verbose && text != nullptr) {
        *text << recording.source << ":" << e.line << ": " << e.request << " -> " << e.answer
              << ": " << (match ? "match" : "MISMATCH") << "\n";
      }
      r.exchanges.push_back(std::move(e));
    }
    if (match) {
      ++r.matched;
      continue;
    }
    Mismatch m;
    m.request_line = step.request->line;
    m.request = session.format(*step.request);
    m.request_summary = request_summary;
    m.answer_index = first;
    m.answers_expected = step.expected.size();
    m.answers_actual = actual.size();
    m.expected_summary = session.describe_answers(*step.request, step.expected);
    m.actual_summary = session.describe_answers(*step.request, actual);
    if (first < step.expected.size()) {
      m.line = step.expected[first].line;
      m.expected = session.format(step.expected[first]);
    }
    if (first < actual.size()) m.actual = session.format(actual[first]);
    if (first < step.expected.size() && first < actual.size()) {
      explain(session, *step.request, step.expected[first], actual[first], m);
      // The later answers of the same request too (a CAN result spans three frames).
      for (std::size_t k = first + 1; k < std::min(actual.size(), step.expected.size()); ++k) {
        Mismatch more;
        explain(session, *step.request, step.expected[k], actual[k], more);
        m.differences.insert(m.differences.end(), more.differences.begin(), more.differences.end());
      }
    } else {
      m.field = "answer count: " + std::to_string(step.expected.size()) + " recorded vs " +
                std::to_string(actual.size()) + " replayed";
    }
    r.mismatches.push_back(std::move(m));
    if (options.max_mismatches != 0 && r.mismatches.size() >= options.max_mismatches) {
      r.stopped_early = s + 1 < steps.size();
      break;
    }
  }
  return r;
}

std::string format_mismatch(const std::string& source, const Mismatch& m) {
  std::string s = "MISMATCH at " + source + ":" +
                  std::to_string(m.line != 0 ? m.line : m.request_line) + " (answer " +
                  std::to_string(m.answer_index + 1) + " of " + std::to_string(m.answers_expected) +
                  " to the request on line " + std::to_string(m.request_line) + ")\n";
  s += "  request:  " + m.request + "\n            " + m.request_summary + "\n";
  s += "  recorded: " + (m.expected.empty() ? std::string("(no answer)") : m.expected) + "\n";
  s += "  replayed: " + (m.actual.empty() ? std::string("(no answer)") : m.actual) + "\n";
  if (m.byte_offset >= 0) {
    s += "  first difference: byte " + std::to_string(m.byte_offset) + ", " + m.field + "\n";
  } else {
    s += "  first difference: " + m.field + "\n";
  }
  for (const std::string& d : m.differences) s += "    " + d + "\n";
  s += "  recorded answer: " + m.expected_summary + "\n";
  s += "  replayed answer: " + m.actual_summary + "\n";
  return s;
}

std::string result_json(const ReplayResult& r) {
  nlohmann::json j;
  j["recording"] = r.source;
  j["format"] = r.format;
  j["target"] = r.target;
  j["requests"] = r.requests;
  j["answers"] = r.answers;
  j["matched"] = r.matched;
  j["skipped"] = {{"heartbeats", r.heartbeats}, {"other", r.other}};
  j["stopped_early"] = r.stopped_early;
  j["ok"] = r.mismatches.empty();
  nlohmann::json list = nlohmann::json::array();
  for (const Mismatch& m : r.mismatches) {
    list.push_back({{"line", m.line},
                    {"request_line", m.request_line},
                    {"request", m.request},
                    {"answer_index", m.answer_index},
                    {"answers_recorded", m.answers_expected},
                    {"answers_replayed", m.answers_actual},
                    {"recorded", m.expected},
                    {"replayed", m.actual},
                    {"byte_offset", m.byte_offset},
                    {"field", m.field},
                    {"differences", m.differences},
                    {"recorded_summary", m.expected_summary},
                    {"replayed_summary", m.actual_summary}});
  }
  j["mismatches"] = list;
  nlohmann::json exchanges = nlohmann::json::array();
  for (const ExchangeLine& e : r.exchanges) {
    exchanges.push_back(
        {{"line", e.line}, {"request", e.request}, {"answer", e.answer}, {"match", e.match}});
  }
  j["exchanges"] = exchanges;
  return j.dump(2);
}

}  // namespace cmmcomp::replay
