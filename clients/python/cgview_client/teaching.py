"""Courses, assignments and grades (protocol/API.md, "Courses, assignments
and grades"; docs/TEACHING.md), as client.courses:

    c = Client(token=TEACHER_TOKEN)
    course = c.courses.create("Geometry Processing")
    enrolled = c.courses.enrol(course["id"], open("roster.csv").read())   # CSV or [{"login", "name"}]
    for link in enrolled["links"]:
        print(link["user"], c.courses.sign_in_url(link["ticket"]))
    a = c.courses.post_assignment(course["id"], title="Distances", hidden_meshes=[m1, m2],
                                  reference_plugin=plugin_id, compare={"method": "relative", "tolerance": 0.03})
    # a student:
    s = Client(token=STUDENT_TOKEN).courses.submit(a["id"], source=open("mine.cpp").read(), wait=True)
    print(s["score"], [r["reason"] for r in s["results"]])
    open("grades.csv", "wb").write(c.courses.grades(a["id"], fmt="csv"))
"""
import json
import time


class Teaching:
    def __init__(self, client):
        self.client = client

    def _path(self, *parts):
        from .client import quote
        return "/" + "/".join(quote(p) for p in parts)

    # --- courses --------------------------------------------------------
    def __call__(self):
        """The courses this token's user is in, each with their role."""
        return self.client.get_json("/courses")

    def create(self, title):
        """A new course (a teacher's: `cgview-server user add NAME --role teacher`)."""
        return self.client.send_json("POST", "/courses", {"title": title})

    def get(self, course_id):
        return self.client.get_json(self._path("courses", course_id))

    def enrol(self, course_id, roster, link_expires_s=None):
        """Adds members: roster is CSV text (login,name[,role] lines) or a
        list of logins or of {"login", "name", "role"}.  New accounts get a
        one-time sign-in link each: {"members", "created", "links"}."""
        query = {"link_expires_s": link_expires_s}
        if isinstance(roster, str):
            body, content_type = roster.encode(), "text/csv"
        else:
            body, content_type = json.dumps(list(roster)).encode(), "application/json"
        data = self.client.request("POST", self._path("courses", course_id, "members"), body, query, content_type)[0]
        return json.loads(data)

    def remove(self, course_id, login):
        self.client.request("DELETE", self._path("courses", course_id, "members", login))

    def new_link(self, course_id, login, link_expires_s=None):
        body = {} if link_expires_s is None else {"link_expires_s": link_expires_s}
        return self.client.send_json("POST", self._path("courses", course_id, "members", login, "link"), body)

    def sign_in_url(self, ticket):
        """The address a student opens to sign in with a link's ticket."""
        return f"{self.client.view_url}/#ticket={ticket}"

    def join(self, code):
        return self.client.send_json("POST", "/courses/join", {"code": code})

    def share(self, kind, item_id, course_id, unshare=False):
        """Shares a mesh, job or plugin (kind "meshes", "jobs", "plugins") with a course's members."""
        return self.client.send_json("POST", self._path(kind, item_id, "unshare" if unshare else "share"),
                                     {"courses": [course_id]})

    # --- assignments ----------------------------------------------------
    def assignments(self, course_id):
        return self.client.get_json(self._path("courses", course_id, "assignments"))

    def post_assignment(self, course_id, **spec):
        """title, statement, starter, public_meshes, hidden_meshes,
        reference_plugin, algorithm, output, params, compare, points_per_mesh,
        deadline ("2026-12-01T23:59:00Z"), show_pictures, time_limit_s."""
        return self.client.send_json("POST", self._path("courses", course_id, "assignments"), spec)

    def assignment(self, assignment_id):
        return self.client.get_json(self._path("assignments", assignment_id))

    def submit(self, assignment_id, source=None, plugin=None, wait=False, timeout=600):
        """Submits C++ source (or a plugin of yours by id); with wait, the graded submission."""
        body = {"source": source} if plugin is None else {"plugin": plugin}
        s = self.client.send_json("POST", self._path("assignments", assignment_id, "submissions"), body)
        return self.wait(s["id"], timeout) if wait else s

    def submission(self, submission_id):
        return self.client.get_json(self._path("submissions", submission_id))

    def wait(self, submission_id, timeout=600):
        """The submission once graded (or failed to build)."""
        deadline = time.monotonic() + timeout
        while True:
            s = self.submission(submission_id)
            if s["state"] in ("graded", "failed"):
                return s
            if time.monotonic() > deadline:
                raise TimeoutError(f"submission {submission_id} is still {s['state']} after {timeout} s")
            time.sleep(0.25)

    def submissions(self, assignment_id):
        return self.client.get_json(self._path("assignments", assignment_id, "submissions"))

    def picture(self, submission_id, n, which="result", width=None, height=None):
        """The PNG of a result's field on hidden mesh n: result, reference or difference."""
        path = self._path("submissions", submission_id, "pictures", str(n), f"{which}.png")
        return self.client.request("GET", path, query={"width": width, "height": height})[0]

    def grades(self, assignment_id, fmt="json", late=False):
        """A row per student (fmt "json"), or the CSV bytes Canvas and Moodle import (fmt "csv")."""
        query = {"format": fmt, "late": "include" if late else "exclude"}
        data = self.client.request("GET", self._path("assignments", assignment_id, "grades"), query=query)[0]
        return json.loads(data) if fmt == "json" else data

    def regrade(self, assignment_id):
        return json.loads(self.client.request("POST", self._path("assignments", assignment_id, "regrade"), b"")[0])
