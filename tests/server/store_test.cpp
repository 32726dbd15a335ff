// The server's store (SQLite rows + blob files) and mesh service (uploads,
// conversions, the Draco cache), without HTTP: records survive a reopen,
// concurrent uploads do not corrupt anything, and an encoding is computed
// once per content and quantization.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sqlite3.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <latch>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/errors.h"
#include "io/mesh_formats.h"
#include "io/mesh_io.h"
#include "mesh_service.h"
#include "stored_order.h"
#include "store.h"
#include "sqlite_query.h"
#include "test_support.h"

namespace cgview::server {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

MeshRecord record(const std::string& name, const std::string& format, std::string_view bytes) {
  MeshRecord r;
  r.name = name;
  r.format = format;
  r.sha256 = sha256_hex(bytes);
  r.report_json = R"({"vertices":1})";
  r.warnings_json = "[]";
  return r;
}

void expect_same(const MeshRecord& a, const MeshRecord& b) {
  EXPECT_EQ(a.id, b.id);
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.format, b.format);
  EXPECT_EQ(a.bytes, b.bytes);
  EXPECT_EQ(a.sha256, b.sha256);
  EXPECT_EQ(a.created, b.created);
  EXPECT_EQ(a.report_json, b.report_json);
  EXPECT_EQ(a.warnings_json, b.warnings_json);
}

// An OFF file of a box, different for every (a, b).
std::string box_off(int a, int b) {
  const double x = a * 10.0, y = b * 10.0;
  return write_mesh_bytes(test::box({x, y, 0}, {x + 1 + a * 0.01, y + 1 + b * 0.01, 1}), MeshFormat::off);
}

TEST(Store, Sha256IsTheKnownDigest) {
  EXPECT_EQ(sha256_hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  EXPECT_EQ(sha256_hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

TEST(Store, AddListGetRemove) {
  const fs::path dir = test::temp_dir("store-crud");
  Store store(dir);
  EXPECT_EQ(store.count(), 0u);
  EXPECT_TRUE(store.list_meshes().empty());

  const std::string a_bytes = box_off(1, 0), b_bytes = box_off(2, 0);
  const MeshRecord a = store.add_mesh(record("a.off", "off", a_bytes), a_bytes);
  const MeshRecord b = store.add_mesh(record("b.off", "off", b_bytes), b_bytes);
  EXPECT_EQ(a.id.size(), 16u);
  EXPECT_EQ(a.id.find_first_not_of("0123456789abcdef"), std::string::npos) << a.id;
  EXPECT_NE(a.id, b.id);
  EXPECT_EQ(a.bytes, a_bytes.size());
  EXPECT_EQ(a.created.size(), 20u) << a.created;  // 2026-11-21T12:00:00Z
  EXPECT_EQ(a.created.back(), 'Z');
  EXPECT_EQ(store.count(), 2u);
  EXPECT_TRUE(fs::exists(dir / "cgview.db"));
  EXPECT_TRUE(fs::exists(dir / "blobs" / (a.id + ".off")));

  const auto list = store.list_meshes();
  ASSERT_EQ(list.size(), 2u);
  expect_same(list[0], a);  // oldest first
  expect_same(list[1], b);

  const auto got = store.get_mesh(b.id);
  ASSERT_TRUE(got.has_value());
  expect_same(*got, b);
  EXPECT_EQ(store.read_blob(*got), b_bytes);
  EXPECT_FALSE(store.get_mesh("0000000000000000").has_value());
  const auto by_sha = store.find_by_sha256(a.sha256);
  ASSERT_TRUE(by_sha.has_value());
  EXPECT_EQ(by_sha->id, a.id);
  EXPECT_FALSE(store.find_by_sha256(sha256_hex("nothing")).has_value());

  EXPECT_TRUE(store.remove_mesh(a.id));
  EXPECT_FALSE(store.remove_mesh(a.id));
  EXPECT_FALSE(store.get_mesh(a.id).has_value());
  EXPECT_FALSE(fs::exists(dir / "blobs" / (a.id + ".off")));
  ASSERT_EQ(store.list_meshes().size(), 1u);
  EXPECT_EQ(store.list_meshes()[0].id, b.id);
  EXPECT_EQ(store.count(), 1u);
}

TEST(Store, CountIsOfTheMeshesTheCallerMayRead) {
  Store store(test::temp_dir("store-count"));
  auto add = [&](const std::string& owner, int k) {
    const std::string bytes = box_off(k, 1);
    MeshRecord r = record("m.off", "off", bytes);
    r.owner = owner;
    return store.add_mesh(std::move(r), bytes).id;
  };
  add("alice", 1);
  add("alice", 2);
  const std::string bobs = add("bob", 3), carols = add("carol", 4);
  store.set_shared("mesh", bobs, {"alice"}, true);
  store.set_shared("mesh", carols, {kEveryone}, true);
  const Caller alice{"alice"}, bob{"bob"}, carol{"carol"}, dave{"dave"}, admin{"root", true};
  // Her own two, bob's shared with her, carol's shared with everyone.
  EXPECT_EQ(store.count(alice), 4u);
  EXPECT_EQ(store.count(bob), 2u);
  EXPECT_EQ(store.count(carol), 1u);
  EXPECT_EQ(store.count(dave), 1u);
  EXPECT_EQ(store.count(admin), 4u);
  for (const Caller& c : {alice, bob, carol, dave, admin})
    EXPECT_EQ(store.count(c), store.list_meshes(c).size()) << c.user;
  store.set_shared("mesh", bobs, {"alice"}, false);
  EXPECT_EQ(store.count(alice), 3u);
  EXPECT_TRUE(store.remove_mesh(carols));
  EXPECT_EQ(store.count(alice), 2u);
  EXPECT_EQ(store.count(dave), 0u);
  EXPECT_EQ(store.count(admin), 3u);
}

TEST(Store, RefusesAnUnsafeFormatName) {
  Store store(test::temp_dir("store-unsafe"));
  EXPECT_THROW(store.add_mesh(record("x", "../x", "abc"), "abc"), InvalidInput);
  EXPECT_THROW(store.add_mesh(record("x", "", "abc"), "abc"), InvalidInput);
  EXPECT_EQ(store.count(), 0u);
}

TEST(Store, ReopeningShowsTheSameRecordsAndBlobs) {
  const fs::path dir = test::temp_dir("store-reopen");
  std::vector<MeshRecord> added;
  std::vector<std::string> bytes;
  {
    Store store(dir);
    for (int i = 0; i < 5; ++i) {
      bytes.push_back(box_off(i, 1));
      std::string name = "m";  // (GCC 12 warns falsely of overlapping copies in "m" + std::to_string(i) + ".off")
      name += std::to_string(i) + ".off";
      added.push_back(store.add_mesh(record(name, "off", bytes.back()), bytes.back()));
    }
    EXPECT_TRUE(store.remove_mesh(added[2].id));
    added.erase(added.begin() + 2);
    bytes.erase(bytes.begin() + 2);
  }
  Store again(dir);
  const auto list = again.list_meshes();
  ASSERT_EQ(list.size(), added.size());
  for (std::size_t i = 0; i < list.size(); ++i) {
    SCOPED_TRACE(i);
    expect_same(list[i], added[i]);
    EXPECT_EQ(again.read_blob(list[i]), bytes[i]);
  }
  EXPECT_EQ(test::integrity_check(dir / "cgview.db"), "ok");
}

// A data directory from before users: its meshes become the local user's,
// and users, tokens and shares are kept across a restart.
TEST(Store, AnOldDataDirectoryUpgradesAndUsersPersist) {
  const fs::path dir = test::temp_dir("store-upgrade");
  {
    sqlite3* db = open_database(dir / "cgview.db");
    exec_sql(
        db,
        "CREATE TABLE meshes (id TEXT PRIMARY KEY, name TEXT NOT NULL, format TEXT NOT NULL, bytes INTEGER NOT NULL,"
        " sha256 TEXT NOT NULL, created TEXT NOT NULL, report TEXT NOT NULL, warnings TEXT NOT NULL, seq INTEGER);"
        "INSERT INTO meshes VALUES ('00000000000000aa', 'old.off', 'off', 3, 'x', '2026-01-01T00:00:00Z', '{}', '[]', "
        "1);",
        "test");
    sqlite3_close(db);
  }
  {
    Store store(dir);
    const auto old = store.get_mesh("00000000000000aa");
    ASSERT_TRUE(old);
    EXPECT_EQ(old->owner, "local");
    EXPECT_FALSE(store.get_mesh(old->id, {"alice", false}));
    store.add_user("alice", false);
    store.add_token("0123456789abcdef", "alice", sha256_hex("secret"));
    store.set_shared("mesh", old->id, {"alice"}, true);
  }
  Store again(dir);
  EXPECT_TRUE(again.get_mesh("00000000000000aa", {"alice", false}));
  EXPECT_EQ(again.list_meshes({"alice", false}).size(), 1u);
  EXPECT_TRUE(again.list_meshes({"bob", false}).empty());
  ASSERT_TRUE(again.find_token("0123456789abcdef"));
  EXPECT_EQ(again.find_token("0123456789abcdef")->first, "alice");
  EXPECT_EQ(again.list_users().size(), 1u);
  EXPECT_EQ(again.revoke_tokens("alice"), 1);
  EXPECT_FALSE(again.find_token("0123456789abcdef"));
  EXPECT_TRUE(again.remove_mesh("00000000000000aa"));
  EXPECT_TRUE(again.shared_with("mesh", "00000000000000aa").empty());
}

TEST(Store, MissingBlobIsAnIoError) {
  const fs::path dir = test::temp_dir("store-missing");
  Store store(dir);
  const std::string bytes = box_off(3, 3);
  const MeshRecord r = store.add_mesh(record("gone.off", "off", bytes), bytes);
  fs::remove(dir / "blobs" / (r.id + ".off"));
  EXPECT_THROW(store.read_blob(r), IoError);
  // The service passes the error on rather than serving nothing.
  MeshService service(store);
  EXPECT_THROW(service.download(r, "off"), IoError);
  EXPECT_THROW(service.draco(r, 14), IoError);
}

TEST(Store, TruncatedBlobIsAnIoError) {
  const fs::path dir = test::temp_dir("store-truncated");
  Store store(dir);
  const std::string bytes = box_off(4, 4);
  const MeshRecord r = store.add_mesh(record("short.off", "off", bytes), bytes);
  test::write_text(dir / "blobs" / (r.id + ".off"), bytes.substr(0, bytes.size() / 2));
  EXPECT_THROW(store.read_blob(r), IoError);
}

TEST(Store, LeftoverPartFilesAreRemovedOnOpen) {
  const fs::path dir = test::temp_dir("store-part");
  { Store store(dir); }
  test::write_text(dir / "blobs" / "0123456789abcdef.off.part", "half");
  Store store(dir);
  EXPECT_FALSE(fs::exists(dir / "blobs" / "0123456789abcdef.off.part"));
}

TEST(Store, UnwritableDirectoryIsAnIoError) {
  const fs::path dir = test::temp_dir("store-bad");
  test::write_text(dir / "file", "x");
  EXPECT_THROW(Store(dir / "file" / "sub"), IoError);
}

TEST(MeshServiceConcurrency, EightThreadsUploadTwentyMeshesEach) {
  const fs::path dir = test::temp_dir("service-concurrent");
  constexpr int kThreads = 8, kEach = 20;
  std::vector<std::vector<std::string>> files(kThreads);
  for (int t = 0; t < kThreads; ++t)
    for (int i = 0; i < kEach; ++i) files[t].push_back(box_off(t, i));
  {
    Store store(dir);
    MeshService service(store);
    std::latch start(kThreads);
    std::atomic<int> failures{0};
    std::vector<std::thread> threads;
    for (int t = 0; t < kThreads; ++t)
      threads.emplace_back([&, t] {
        start.arrive_and_wait();
        for (int i = 0; i < kEach; ++i) {
          try {
            char name[32];
            std::snprintf(name, sizeof name, "t%d_%d.off", t, i);
            const MeshRecord r = service.upload(name, "", files[t][i]);
            if (r.sha256 != sha256_hex(files[t][i])) ++failures;
          } catch (const std::exception& e) {
            ADD_FAILURE() << "upload failed: " << e.what();
            ++failures;
          }
        }
      });
    for (auto& th : threads) th.join();
    EXPECT_EQ(failures.load(), 0);
    EXPECT_EQ(store.count(), std::size_t(kThreads * kEach));
  }
  // Reopened: every record, every blob intact.
  Store store(dir);
  const auto list = store.list_meshes();
  ASSERT_EQ(list.size(), std::size_t(kThreads * kEach));
  std::set<std::string> ids, shas, expected;
  for (const auto& f : files)
    for (const auto& b : f) expected.insert(sha256_hex(b));
  for (const MeshRecord& r : list) {
    ids.insert(r.id);
    shas.insert(r.sha256);
    const std::string blob = store.read_blob(r);
    EXPECT_EQ(blob.size(), r.bytes);
    EXPECT_EQ(sha256_hex(blob), r.sha256) << r.name;
    const json report = json::parse(r.report_json);
    EXPECT_EQ(report["vertices"], 8) << r.name;
    EXPECT_EQ(report["faces"], 12) << r.name;
    const int t = std::stoi(r.name.substr(1)), i = std::stoi(r.name.substr(r.name.find('_') + 1));
    EXPECT_EQ(blob, files[t][i]) << r.name;
  }
  EXPECT_EQ(ids.size(), list.size());
  EXPECT_EQ(shas, expected);
  std::size_t blob_files = 0;
  for (const auto& e : fs::directory_iterator(dir / "blobs")) {
    EXPECT_EQ(e.path().extension(), ".off") << e.path();
    ++blob_files;
  }
  EXPECT_EQ(blob_files, list.size());
  EXPECT_EQ(test::integrity_check(dir / "cgview.db"), "ok");
}

TEST(MeshService, UploadReportsAndRefusesBadInput) {
  Store store(test::temp_dir("service-upload"));
  MeshService service(store);
  const std::string bytes = box_off(0, 0);
  const MeshRecord r = service.upload("box.off", "", bytes);
  EXPECT_EQ(r.format, "off");
  const json j = mesh_json(r);
  EXPECT_EQ(j["id"], r.id);
  EXPECT_EQ(j["name"], "box.off");
  EXPECT_EQ(j["bytes"], bytes.size());
  EXPECT_EQ(j["report"]["vertices"], 8);
  EXPECT_EQ(j["report"]["faces"], 12);
  EXPECT_TRUE(j["warnings"].is_array());
  // The format parameter wins over the name.
  EXPECT_EQ(service.upload("box.bin", "off", bytes).format, "off");
  EXPECT_THROW(service.upload("", "", bytes), InvalidInput);
  EXPECT_THROW(service.upload("a/b.off", "", bytes), InvalidInput);
  EXPECT_THROW(service.upload("box.las", "", bytes), UnsupportedFormat);
  EXPECT_THROW(service.upload("bad.off", "", "OFF\n3 1 0\n0 0 0\n"), InvalidInput);
  EXPECT_EQ(store.count(), 2u);
}

TEST(MeshService, DownloadConvertsAndReturnsTheOriginal) {
  Store store(test::temp_dir("service-download"));
  MeshService service(store);
  const std::string bytes = box_off(5, 5);
  const MeshRecord r = service.upload("box.off", "", bytes);
  EXPECT_EQ(service.download(r, "off"), bytes);
  for (const MeshFormatInfo& writable : mesh_formats()) {
    if (!writable.write || writable.format == MeshFormat::off) continue;
    const std::string f = writable.name;
    SCOPED_TRACE(f);
    const std::string out = service.download(r, f);
    const Mesh m = read_mesh_bytes(out, writable.format, "download").mesh;
    EXPECT_EQ(m.num_faces(), writable.points_only ? 0u : 12u);  // XYZ: the vertices as a cloud
    EXPECT_EQ(m.num_vertices(), 8u);
  }
  EXPECT_THROW(service.download(r, "gltf"), UnsupportedFormat);
  EXPECT_THROW(service.download(r, "las"), UnsupportedFormat);
}

// A cloud's stream is a Draco point cloud with its normals and colours, its
// points in the stored order, and it gets no preview however big.
TEST(MeshService, APointCloudStreamsAsADracoPointCloudInItsOrder) {
  Store store(test::temp_dir("service-points"));
  MeshService service(store);
  service.set_preview({.threshold_faces = 1, .target_faces = 1});
  std::string xyz;
  for (int i = 0; i < 300; ++i) xyz += std::to_string(i) + " " + std::to_string(i % 7) + " 1 0 0 1\n";
  const MeshRecord r = service.upload("scan.xyz", "", xyz);
  EXPECT_FALSE(service.has_preview(r));
  const auto enc = service.draco(r, 14);
  EXPECT_EQ(enc->vertices, 300u);
  EXPECT_EQ(enc->faces, 0u);
  EXPECT_TRUE(enc->has_normals);
  const Mesh decoded = read_mesh_bytes(enc->bytes, MeshFormat::drc, "stream").mesh;
  ASSERT_EQ(decoded.num_vertices(), 300u);
  EXPECT_EQ(decoded.num_faces(), 0u);
  EXPECT_EQ(decoded.normals.size(), 300u);
  EXPECT_NEAR(decoded.positions[123].x, 123, 0.05);
  EXPECT_NEAR(decoded.positions[123].y, 123 % 7, 0.05);
  const protocol::StoredOrder order = protocol::unpack_stored_order(service.stored_order(r, 14));
  ASSERT_EQ(order.points.size(), 300u);
  for (std::uint32_t i = 0; i < 300; ++i) EXPECT_EQ(order.points[i], i);
  EXPECT_TRUE(order.faces.empty());
}

TEST(MeshServiceCache, SecondDracoCallIsServedFromTheCache) {
  Store store(test::temp_dir("service-cache"));
  MeshService service(store);
  const std::string bytes = box_off(6, 6);
  const MeshRecord r = service.upload("box.off", "", bytes);
  EXPECT_EQ(service.encodings_computed(), 0u);
  const auto first = service.draco(r, 14);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->vertices, 8u);
  EXPECT_EQ(first->faces, 12u);
  EXPECT_EQ(first->bytes.substr(0, 5), "DRACO");
  EXPECT_EQ(service.encodings_computed(), 1u);
  const auto second = service.draco(r, 14);
  EXPECT_EQ(second.get(), first.get());
  EXPECT_EQ(service.encodings_computed(), 1u);
  // Same content under another record: the cache is by content.
  const MeshRecord twin = service.upload("twin.off", "", bytes);
  EXPECT_EQ(service.draco(twin, 14).get(), first.get());
  EXPECT_EQ(service.encodings_computed(), 1u);
  // The download in drc is the default quantization's cached encoding.
  EXPECT_EQ(service.download(r, "drc"), first->bytes);
  EXPECT_EQ(service.encodings_computed(), 1u);
  // Another quantization is another encoding.
  const auto coarse = service.draco(r, 8);
  EXPECT_NE(coarse.get(), first.get());
  EXPECT_EQ(service.encodings_computed(), 2u);
  EXPECT_THROW(service.draco(r, 0), InvalidInput);
  EXPECT_THROW(service.draco(r, 31), InvalidInput);
  EXPECT_EQ(service.encodings_computed(), 2u);
}

TEST(MeshServiceCache, EightConcurrentFirstCallsComputeOnce) {
  const fs::path dir = test::temp_dir("service-cache-concurrent");
  Store store(dir);
  MeshRecord r;
  {
    MeshService loader(store);
    r = loader.upload("elephant.off", "", read_file_bytes(test::sample("elephant.off"), 1 << 30));
  }
  // A fresh service: nothing parsed or encoded in memory yet.
  MeshService service(store);
  constexpr int kThreads = 8;
  std::latch start(kThreads);
  std::vector<std::shared_ptr<const EncodedMesh>> got(kThreads);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      start.arrive_and_wait();
      got[t] = service.draco(r, 12);
    });
  for (auto& th : threads) th.join();
  EXPECT_EQ(service.encodings_computed(), 1u);
  for (int t = 0; t < kThreads; ++t) {
    ASSERT_TRUE(got[t]);
    EXPECT_EQ(got[t].get(), got[0].get()) << "thread " << t;
  }
  EXPECT_EQ(got[0]->vertices, 2775u);
  EXPECT_EQ(got[0]->faces, 5558u);
}

TEST(MeshServiceCache, AFailedEncodingIsNotCached) {
  const fs::path dir = test::temp_dir("service-cache-fail");
  Store store(dir);
  const std::string bytes = box_off(7, 7);
  MeshRecord r;
  {
    MeshService loader(store);
    r = loader.upload("box.off", "", bytes);
  }
  MeshService service(store);
  fs::rename(dir / "blobs" / (r.id + ".off"), dir / "aside");
  EXPECT_THROW(service.draco(r, 14), IoError);
  EXPECT_EQ(service.encodings_computed(), 0u);
  fs::rename(dir / "aside", dir / "blobs" / (r.id + ".off"));
  const auto enc = service.draco(r, 14);  // retried, not the stored failure
  EXPECT_EQ(enc->faces, 12u);
  EXPECT_EQ(service.encodings_computed(), 1u);
}

}  // namespace
}  // namespace cgview::server
