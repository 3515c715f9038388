#include "rangekit/core/spike_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "rangekit/core/family.hpp"

namespace rangekit {
namespace {

// The median of the first `size` values (reordered); on the stack, as it runs for every reading.
double median_of(std::array<double, SpikeCheck::window>& values, std::size_t size) {
  const auto end = values.begin() + static_cast<std::ptrdiff_t>(size);
  const auto middle = values.begin() + static_cast<std::ptrdiff_t>(size / 2);
  std::nth_element(values.begin(), middle, end);
  if (size % 2 == 1) return *middle;
  return (*middle + *std::max_element(values.begin(), middle)) / 2;
}

}  // namespace

std::optional<SpikeCheck::Judged> SpikeCheck::judged(const Sample& sample) {
  const auto input = quality_input_of(sample);
  if (!input || !input->distance_m || !std::isfinite(*input->distance_m) || !input->scale) return std::nullopt;
  return Judged{*input->distance_m, input->scale->accuracy_m, input->scale->resolution_m};
}

double SpikeCheck::Level::median() const {
  if (size == 0) return 0;
  const std::size_t middle = size / 2;
  return size % 2 == 1 ? sorted[middle] : (sorted[middle] + sorted[middle - 1]) / 2;
}

void SpikeCheck::Level::push(double value) {
  if (size >= min_level) {
    mean_deviation += (std::abs(value - median()) - mean_deviation) / 128;
  } else if (size > 0) {
    mean_deviation += (std::abs(value - values[(next + window - 1) % window]) / std::sqrt(2.0) - mean_deviation) /
                      static_cast<double>(size + 1);  // until the level is known: from successive readings
  }
  // The sorted copy follows the window: the oldest value out, the new one in at its place.
  auto end = sorted.begin() + static_cast<std::ptrdiff_t>(size);
  if (size == window) {
    const auto oldest = std::lower_bound(sorted.begin(), end, values[next]);
    std::move(oldest + 1, end, oldest);
    --end;
  }
  const auto at = std::upper_bound(sorted.begin(), end, value);
  std::move_backward(at, end, end + 1);
  *at = value;
  values[next] = value;
  next = (next + 1) % window;
  size = std::min(size + 1, window);
}

// `held` is a spike when it is further than the allowance from the level of the readings
// before it and the one after it did not stay with it. The allowance is the sensor's stated
// accuracy plus three standard errors of the level (a median of up to 101 readings, their
// spread learnt from about the last 128) plus one step of resolution: an honest reading of a
// still target is within the accuracy of the truth, and the level within those errors of it.
void SpikeCheck::judge(Stream& stream, Sample& held, const Sample& next,
                       const std::optional<Judged>& next_reading) const {
  const Judged* p = &stream.held_reading;
  const auto& n = next_reading;
  if (!n || held.kind != next.kind || stream.level.size < min_level || held.suspect) return;
  const std::size_t size = stream.level.size;
  const double level = stream.level.median();
  const double sigma = 1.2533 * stream.level.mean_deviation;  // a mean absolute deviation, as a standard deviation
  const double level_error = 1.2533 * sigma / std::sqrt(static_cast<double>(size));
  const double allowed = p->accuracy_m + 3 * level_error + p->resolution_m;
  if (std::abs(p->value_m - level) <= allowed) return;
  const bool back = std::abs(n->value_m - level) <= allowed;
  const bool next_apart = std::abs(p->value_m - n->value_m) > allowed / 2;
  // A still target (the newest quarter of the window has the level of the whole): the next
  // reading only has to be far from this one, and not further out on the same side (then this
  // one is a step on its way, a reading between two targets), so that a spike beside a second
  // corrupted reading is still seen. A moving target's level lags it by half a window of its
  // travel, so a moving reading is judged by its neighbours instead: far from the midpoint of
  // the one before and the one after, which lie close together.
  std::array<double, window> recent{};
  const std::size_t quarter = size / 4;
  for (std::size_t i = 0; i < quarter; ++i) {
    recent[i] = stream.level.values[(stream.level.next + window - 1 - i) % window];
  }
  const bool still = std::abs(median_of(recent, quarter) - level) <= allowed / 4;
  const double p_off = p->value_m - level;
  const double n_off = n->value_m - level;
  const bool stepping = (p_off > 0) == (n_off > 0) && std::abs(n_off) >= std::abs(p_off);
  // The midpoint carries its readings' error as well as this one its own: twice the accuracy.
  const double from_neighbours = allowed + p->accuracy_m;
  const bool between_neighbours = stream.last && std::abs(*stream.last - n->value_m) <= allowed &&
                                  std::abs(p->value_m - (*stream.last + n->value_m) / 2) > from_neighbours;
  const bool spike =
      still ? (back && next_apart) || (std::abs(p->value_m - n->value_m) > allowed && !stepping) : between_neighbours;
  if (!spike) return;
  held.suspect = true;
  std::array<char, 200> text{};
  if (still) {
    std::snprintf(text.data(), text.size(),
                  "spike: %.6f m, %.6f m from the level %.6f m of the last readings, and the next not with it "
                  "(%.6f m); at most %.6f m",
                  p->value_m, p->value_m - level, level, n->value_m, allowed);
  } else {
    const double midpoint = (*stream.last + n->value_m) / 2;
    std::snprintf(text.data(), text.size(),
                  "spike: %.6f m, %.6f m from the midpoint of the readings before (%.6f m) and after (%.6f m); "
                  "at most %.6f m",
                  p->value_m, p->value_m - midpoint, *stream.last, n->value_m, from_neighbours);
  }
  held.suspect_reason = text.data();
}

void SpikeCheck::release(Stream& stream, std::vector<StreamItem>& out) {
  if (!stream.held) return;
  // A held reading always has what it is judged on (only those are held).
  if (const Judged& reading = stream.held_reading; !stream.held->suspect) {
    stream.level.push(reading.value_m);
    stream.last = reading.value_m;
  } else if (stream.held->suspect_reason.rfind("spike", 0) != 0) {
    stream.level.push(reading.value_m);  // a jump the other check flagged may be a real step: the level follows
  }
  out.emplace_back(std::move(*stream.held));
  stream.held.reset();
  for (StreamEvent& event : stream.waiting) out.emplace_back(std::move(event));
  stream.waiting.clear();
  --held_count_;
}

namespace {

bool is_link_event(StreamEventKind kind) {
  return kind == StreamEventKind::connected || kind == StreamEventKind::disconnected ||
         kind == StreamEventKind::reconnected || kind == StreamEventKind::polling;
}

}  // namespace

void SpikeCheck::push(StreamItem item, std::chrono::steady_clock::time_point now, std::vector<StreamItem>& out) {
  if (auto* sample = std::get_if<Sample>(&item)) return push_sample(std::move(*sample), now, out);
  auto& event = std::get<StreamEvent>(item);
  if (held_count_ == 0) {
    out.push_back(std::move(item));
    return;
  }
  if (is_link_event(event.kind)) {
    release_all(out);
    out.push_back(std::move(item));
    return;
  }
  // Behind the newest held reading, so that a bad frame after a spike does not let the spike
  // go unjudged; a storm of them lets it go.
  Stream* newest = nullptr;
  for (auto& [key, stream] : streams_) {
    if (stream.held && (newest == nullptr || stream.held_order > newest->held_order)) newest = &stream;
  }
  if (newest == nullptr) {  // held_count_ out of step with the streams: pass it on, never lose it
    out.push_back(std::move(item));
    return;
  }
  newest->waiting.push_back(std::move(event));
  if (newest->waiting.size() >= max_waiting) release(*newest, out);
}

void SpikeCheck::push_sample(Sample sample, std::chrono::steady_clock::time_point now, std::vector<StreamItem>& out) {
  Stream& stream = streams_[Key{sample.device, sample.source, sample.address}];
  const std::optional<Judged> reading = judged(sample);
  if (stream.held) {
    judge(stream, *stream.held, sample, reading);
    release(stream, out);
  }
  if (!stream.first_arrival) stream.first_arrival = now;
  stream.last_arrival = now;
  ++stream.arrivals;
  const auto period = stream.arrivals < 3 ? std::chrono::steady_clock::duration::max()
                                          : (stream.last_arrival - *stream.first_arrival) /
                                                static_cast<std::int64_t>(stream.arrivals - 1);
  if (!reading || period > settings_.hold_limit) {
    // Not held: it joins the level at once (a slow stream is never judged, but keeps a level).
    if (reading) {
      stream.level.push(reading->value_m);
      if (!sample.suspect) stream.last = reading->value_m;
    }
    out.emplace_back(std::move(sample));
    return;
  }
  stream.held = std::move(sample);
  stream.held_reading = *reading;
  stream.held_at = now;
  stream.held_order = ++order_;
  ++held_count_;
}

void SpikeCheck::release_all(std::vector<StreamItem>& out) {
  std::vector<Stream*> holding;
  for (auto& [key, stream] : streams_) {
    if (stream.held) holding.push_back(&stream);
  }
  std::sort(holding.begin(), holding.end(),
            [](const Stream* a, const Stream* b) { return a->held_order < b->held_order; });
  for (Stream* stream : holding) release(*stream, out);
}

void SpikeCheck::release_due(std::chrono::steady_clock::time_point now, std::vector<StreamItem>& out) {
  if (held_count_ == 0) return;
  std::vector<Stream*> due;
  for (auto& [key, stream] : streams_) {
    if (stream.held && now - stream.held_at > settings_.hold_limit) due.push_back(&stream);
  }
  std::sort(due.begin(), due.end(), [](const Stream* a, const Stream* b) { return a->held_order < b->held_order; });
  for (Stream* stream : due) release(*stream, out);
}

}  // namespace rangekit
