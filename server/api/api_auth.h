// Who may use the robot, managed: the first admin's setup, browser sessions (login and logout), users, API tokens and
// the audit log. The gate that applies it to every request is Api's (api.h).
#pragma once

#include <string>

#include "server/api/router.h"
#include "server/auth/gate.h"

namespace corridor::server {

class AccountsApi {
 public:
  // `secure`: the server speaks TLS (session cookies are Secure). `tls_fingerprint`: the server certificate's SHA-256,
  // shown at setup; "" without TLS.
  AccountsApi(auth::AccessControl& access, bool secure, std::string tls_fingerprint);
  void AddRoutes(Router& routes) const;

 private:
  auth::AccessControl& access_;
  bool secure_;
  std::string tls_fingerprint_;
};

}  // namespace corridor::server
