#include "router_harness.h"

#include <system_error>
#include <utility>

#include "auth.h"
#include "test_support.h"

namespace cgview::test {

void RouterFixture::make_dir(const std::string& tag) {
  dir_ = temp_dir(tag + ::testing::UnitTest::GetInstance()->current_test_info()->name());
}

void RouterFixture::open(const std::filesystem::path& store_dir, std::optional<server::JobConfig> jobs,
                         server::RouterConfig rc) {
  store_ = std::make_unique<server::Store>(store_dir);
  meshes_ = std::make_unique<server::MeshService>(*store_);
  // Uploads read in a child, as the server reads them.
  meshes_->set_reader({bin("cgview-read"), store_dir / "tmp"});
  if (jobs) {
    jobs->worker = bin("cgview-worker-test");
    jobs_ = std::make_unique<server::JobScheduler>(*meshes_, std::move(*jobs));
    // Users' plugins beside the jobs, as the server has them (unsandboxed here:
    // the router's tests build none).
    plugins_ = std::make_unique<server::PluginService>(*store_, *jobs_, server::PluginConfig{});
    jobs_->set_plugin_resolver(
        [p = plugins_.get()](const std::string& id, const std::string& algorithm, const server::Caller& caller) {
          return p->resolve(id, algorithm, caller);
        });
    jobs_->start();
    rc.jobs = jobs_.get();
    rc.plugins = plugins_.get();
  }
  // Courses, and assignments where there are jobs, as the server has them.
  courses_ = std::make_unique<server::Courses>(*store_);
  rc.courses = courses_.get();
  rooms_ = std::make_unique<server::Rooms>(
      *store_, *courses_, [](const nlohmann::json&, const server::Access&) {},
      [](const std::string&, const std::string&, const server::Caller&) { return false; });
  rc.rooms = rooms_.get();
  if (jobs_) {
    grading_ = std::make_unique<server::Grading>(*meshes_, *courses_, *jobs_, *plugins_);
    rc.grading = grading_.get();
  }
  router_ = std::make_unique<server::Router>(*meshes_, std::move(rc));
}

void RouterFixture::open_with_users(const std::filesystem::path& dir, server::JobConfig jobs) {
  server::RouterConfig rc;
  rc.auth_required = true;
  open(dir, std::move(jobs), std::move(rc));
  server::Auth auth(*store_, true);
  alice_ = auth.add_user("alice", false);
  bob_ = auth.add_user("bob", false);
}

void RouterFixture::TearDown() {
  router_.reset();
  if (grading_) grading_->stop();
  if (plugins_) plugins_->stop();
  jobs_.reset();
  grading_.reset();
  rooms_.reset();
  courses_.reset();
  plugins_.reset();
  meshes_.reset();
  store_.reset();
  std::error_code ec;
  if (!HasFailure() && !dir_.empty()) std::filesystem::remove_all(dir_, ec);
}

}  // namespace cgview::test
