// A fixture for the suites that call the HTTP router directly (no sockets):
// a fresh directory, a store, its mesh service, optionally a job scheduler
// on the test worker, and the router over them, closed in the right order.
// Shared by router_test, texture_upload_test, auth_test and quota_test.
#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <memory>
#include <optional>
#include <string>

#include "jobs/scheduler.h"
#include "mesh_service.h"
#include "plugin_service.h"
#include "router.h"
#include "server_harness.h"  // read_bytes
#include "store.h"
#include "teaching/courses.h"
#include "teaching/grading.h"
#include "teaching/rooms.h"

namespace cgview::test {

class RouterFixture : public ::testing::Test {
 protected:
  // dir_ = a fresh temp directory named TAG + the test's name.
  void make_dir(const std::string& tag);

  // A store in STORE_DIR and its mesh service (uploads read by cgview-read
  // in a child process, as the server does); with JOBS, a scheduler on the
  // test worker (cgview-worker-test), started, and rc.jobs set to it; then
  // the router with RC.
  void open(const std::filesystem::path& store_dir, std::optional<server::JobConfig> jobs, server::RouterConfig rc);

  // open() in DIR with JOBS and users required, then users alice_ and bob_
  // (their tokens; not admins).
  void open_with_users(const std::filesystem::path& dir, server::JobConfig jobs);

  // Closes the router, the scheduler, the service and the store; removes
  // dir_ unless the test failed (kept for a look).
  void TearDown() override;

  std::filesystem::path dir_;
  std::unique_ptr<server::Store> store_;
  std::unique_ptr<server::MeshService> meshes_;
  std::unique_ptr<server::JobScheduler> jobs_;
  std::unique_ptr<server::PluginService> plugins_;
  std::unique_ptr<server::Courses> courses_;
  std::unique_ptr<server::Grading> grading_;
  std::unique_ptr<server::Rooms> rooms_;
  std::unique_ptr<server::Router> router_;
  std::string alice_, bob_;
};

}  // namespace cgview::test
