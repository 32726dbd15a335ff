"""client.courses against the real server: a teacher's course, a roster's
sign-in link redeemed, an assignment graded on a hidden mesh, a wrong and a
right submission scored, and the grades as CSV."""
import json
import os
import subprocess
import unittest

import harness
from cgview_client import CGViewError, Client

HEIGHT = os.path.join(harness.REPO, "docs", "examples", "height.cpp")
server = None


def setUpModule():
    global server
    server = harness.Server(users=("alice",), args=("--auth", "required"))


def tearDownModule():
    server.stop()


class TeachingTest(unittest.TestCase):
    def test_a_course_from_roster_to_grades(self):
        teacher_token = subprocess.run([harness.SERVER, "--data-dir", server.data_dir, "user", "add", "tina", "--role",
                                        "teacher"], check=True, capture_output=True, text=True).stdout.strip()
        teacher = Client(server.url, token=teacher_token)
        with self.assertRaises(CGViewError) as refused:
            Client(server.url, token=server.tokens["alice"]).courses.create("Mine")
        self.assertEqual(refused.exception.status, 403)
        course = teacher.courses.create("Geometry Processing")
        enrolled = teacher.courses.enrol(course["id"], "login,name\nsam,Sam S\n")
        self.assertEqual(enrolled["created"], ["sam"])
        self.assertTrue(teacher.courses.sign_in_url(enrolled["links"][0]["ticket"]).endswith(
            "/#ticket=" + enrolled["links"][0]["ticket"]))
        # The link, redeemed by a client without a token, signs sam in.
        signed_in = Client(server.url).send_json("POST", "/tickets/redeem", {"ticket": enrolled["links"][0]["ticket"]})
        sam = Client(server.url, token=signed_in["token"])
        self.assertEqual([c["role"] for c in sam.courses()], ["student"])

        with open(HEIGHT) as f:
            source = f.read()
        hidden = teacher.upload(harness.ELEPHANT)
        plugin = teacher.send_json("POST", "/plugins", {"name": "height", "source": source})
        build = teacher.request("POST", f"/plugins/{plugin['id']}/build", b"")[0]
        self.assertEqual(teacher.wait(json.loads(build)["id"], timeout=120)["state"], "done")
        a = teacher.courses.post_assignment(course["id"], title="Height", statement="# Height",
                                            hidden_meshes=[hidden["id"]], reference_plugin=plugin["id"],
                                            compare={"method": "relative", "tolerance": 0.01}, points_per_mesh=4)
        self.assertEqual(sam.courses.assignment(a["id"])["hidden_count"], 1)
        wrong = sam.courses.submit(a["id"], source=source.replace("HeightAxis axis = HeightAxis::z",
                                                                  "HeightAxis axis = HeightAxis::y"), wait=True)
        self.assertEqual((wrong["state"], wrong["score"]), ("graded", 0), wrong)
        self.assertIn("allowed", wrong["results"][0]["reason"])
        right = sam.courses.submit(a["id"], source=source, wait=True)
        self.assertEqual((right["state"], right["score"], right["max_score"]), ("graded", 4, 4), right)
        csv = teacher.courses.grades(a["id"], fmt="csv").decode()
        self.assertIn("\nSam S,,sam,sam,,4,2,", csv)
        self.assertEqual([r["score"] for r in teacher.courses.grades(a["id"])["students"]], [4])


if __name__ == "__main__":
    unittest.main()
