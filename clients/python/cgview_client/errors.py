"""The client's errors: the server's error answers, and jobs that failed."""


class CGViewError(Exception):
    """An error answer of the server: HTTP status, error code, detail and,
    for a bad parameter, its name.  Over a quota (413 storage_quota, 429
    job_limit) the detail names the limit and the use, .limit and .used are
    the numbers, and for 429 .retry_after the seconds to wait."""

    def __init__(self, status, error, detail, parameter=None, limit=None, used=None, retry_after=None):
        super().__init__(f"HTTP {status} {error}: {detail}")
        self.status, self.error, self.detail, self.parameter = status, error, detail, parameter
        self.limit, self.used, self.retry_after = limit, used, retry_after


class JobFailed(Exception):
    """A job that ended in another state than done; .job is its last state."""

    def __init__(self, job):
        super().__init__(f"job {job['id']} ({job['algorithm']}) {job['state']}: {job.get('error') or 'no error given'}")
        self.job = job
