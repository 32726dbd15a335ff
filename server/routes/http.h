// The HTTP vocabulary every route uses, without sockets: requests and
// responses as values, the error body, the query string, typed query
// parameters that name themselves when wrong, and content types.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace cgview::server {

struct HttpRequest {
  std::string method;  // "GET"
  std::string target;  // "/api/v1/meshes?name=x.off"
  std::string body;
  std::string authorization;  // the Authorization header ("Bearer TOKEN"), or empty
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
};

// A JSON response (a detail quoting a file's invalid UTF-8 is replaced, not a reason to fail).
HttpResponse json_response(int status, const nlohmann::json& body);
// An error response: {"error": code, "detail": detail}.
HttpResponse error_response(int status, const std::string& code, const std::string& detail);

// Splits "/a/b?x=1&y=%20" into its path and decoded query parameters.
std::pair<std::string, std::map<std::string, std::string>> split_target(const std::string& target);

// The content type of a file extension (".png"); application/octet-stream for others.
const char* content_type_of(const std::string& extension);

// A 400 naming the query parameter at fault ("parameter" in its JSON).
struct BadParameter : std::runtime_error {
  BadParameter(std::string name, const std::string& detail) : std::runtime_error(detail), parameter(std::move(name)) {}
  std::string parameter;
};
HttpResponse bad_parameter(const BadParameter& e);

using Query = std::map<std::string, std::string>;
// A finite number, or `fallback` when absent; throws BadParameter.
double number_param(const Query& q, const std::string& name, double fallback);
// An integer, or `fallback` when absent; throws BadParameter.
int int_param(const Query& q, const std::string& name, int fallback);
// A text, or `fallback` when absent.
std::string text_param(const Query& q, const std::string& name, const std::string& fallback = "");

}  // namespace cgview::server
