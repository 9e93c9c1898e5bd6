#pragma once
// The viewer's playback clock for a rig's animation (window-free, unit-tested): the time slider's value,
// advanced by wall-clock time while playing, wrapping around [start, end] (loop) or stopping at the end.
//
//   AnimationClock c{.start = 0, .end = 2};
//   c.playing = true;
//   if (c.advance(frame_seconds)) session.set_time(c.time);
#include <algorithm>
#include <cmath>

namespace spinmotor::viewer {

struct AnimationClock {
  double start = 0.0, end = 0.0;  ///< the animation's key range (seconds)
  double time = 0.0;              ///< the current time
  double speed = 1.0;             ///< animation seconds per wall-clock second (> 0)
  bool playing = false;
  bool loop = true;  ///< wrap to start past the end; else stop there (and stop playing)

  /// Advances by dt ≥ 0 wall-clock seconds while playing. Returns true when the time changed.
  bool advance(double dt) {
    if (!playing || !(dt > 0) || !(speed > 0)) return false;
    const double before = time, length = end - start;
    if (!(length > 0)) {  // a single key: nothing to play
      time = start;
      return time != before;
    }
    time += dt * speed;
    if (time > end) {
      if (loop) {
        time = start + std::fmod(time - start, length);
      } else {
        time = end;
        playing = false;
      }
    }
    time = std::clamp(time, start, end);
    return time != before;
  }
};

}  // namespace spinmotor::viewer
