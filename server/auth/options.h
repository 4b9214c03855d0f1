// The auth: section of the configuration (server/config/config.h reads it; server/auth/gate.h applies it).
#pragma once

namespace corridor::server::auth {

struct AuthOptions {
  bool anonymous_viewer = false;       // reads without logging in
  bool local_face = true;              // the robot's own screen (loopback) may show the face and the setup code
  double session_hours = 12.0;         // a browser session lapses this long after its last use
  int login_failures_per_minute = 10;  // per client address and per username; beyond, 429 until the minute passes
  int keep_audit = 100000;             // audit records kept
};

}  // namespace corridor::server::auth
