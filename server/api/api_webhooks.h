// Building systems that want to be told what happens: /api/v1/webhooks (subscriptions kept in the database, and their
// recent deliveries), a ping to check one works, and /api/v1/events (the robot's events as the database keeps them,
// for a system that polls instead).
#pragma once

#include "server/api/router.h"
#include "server/api/webhooks.h"
#include "server/config/config.h"
#include "server/store/store.h"

namespace corridor::server {

class WebhooksApi {
 public:
  // `webhooks` is used on the io executor, as the handlers are.
  WebhooksApi(Store& store, Webhooks& webhooks, const WebhookOptions& options);
  void AddRoutes(Router& routes) const;

 private:
  Store& store_;
  Webhooks& webhooks_;
  const WebhookOptions& options_;
};

}  // namespace corridor::server
