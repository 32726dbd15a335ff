// POST /api/v1/data: data another tool made (a voxel grid, a curve skeleton,
// a scalar field for a stored mesh), read as mesh uploads are (in a child
// process, under the same limits) and kept as a done job's artifact, so that
// it shows, slices, compares and feeds jobs as a job's result does.
#include "data_read.h"
#include "jobs/scheduler.h"
#include "mesh_service.h"
#include "router.h"
#include "routes/routes.h"
#include "store.h"

namespace cgview::server {

using nlohmann::json;

void add_data_routes(Routes& routes, const RouteContext& ctx) {
  routes.push_back(
      {"POST",
       "/api/v1/data",
       "Upload data another tool made (a voxel grid, a skeleton, or a scalar field for a stored mesh): the file's "
       "bytes as the raw body; it becomes a done job's artifact",
       {{"name", "the file name, e.g. grid.nrrd, tree.polylines.txt, sdf.ply or values.txt (required)"},
        {"kind", "voxel_grid, skeleton or scalar_field (default: from the name)"},
        {"mesh", "the stored mesh a scalar field is for (required for a field)"},
        {"property", "the PLY property to take as the field (default: its first)"}},
       [&ctx](const Params&, const HttpRequest& req, const Caller& caller) {
         const auto q = split_target(req.target).second;
         auto param = [&](const char* key) {
           const auto it = q.find(key);
           return it == q.end() ? std::string() : it->second;
         };
         if (param("name").empty()) return error_response(400, "bad_request", "the query needs ?name=FILE.EXT");
         DataRequest data{clean_upload_name(param("name")), param("kind"), param("property")};
         data_kind(data.name, data.kind);  // a name of no known kind is refused before anything is read
         JobScheduler& jobs = ctx.jobs();
         jobs.check_storage(caller, req.body.size(), "this upload");
         json inputs = json::object();
         if (!param("mesh").empty()) {
           const MeshRecord rec = ctx.mesh(param("mesh"), caller);
           const json report = json::parse(rec.report_json, nullptr, false);
           data.for_mesh = true;
           data.mesh_vertices = report.is_object() ? report.value("vertices", std::size_t(0)) : 0;
           data.mesh_faces = report.is_object() ? report.value("faces", std::size_t(0)) : 0;
           inputs["mesh"] = rec.id;
         }
         // Read by cgview-read-data, beside the mesh uploads' cgview-read, under the same limits.
         UploadReader reader = ctx.meshes.reader();
         if (!reader.program.empty()) reader.program = reader.program.parent_path() / "cgview-read-data";
         const json job = jobs.import_data(
             data.name, inputs,
             [&](const std::filesystem::path& dir) {
               DataRead d = reader.program.empty() ? read_data(data, req.body, dir)
                                                   : read_data_in_child(reader, data, req.body, dir);
               return std::pair{std::move(d.entry), std::move(d.warnings)};
             },
             caller);
         HttpResponse r = json_response(201, job);
         r.headers.push_back({"Location", "/api/v1/jobs/" + job["id"].get<std::string>()});
         return r;
       }});
}

}  // namespace cgview::server
