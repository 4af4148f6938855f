// The MD engine (issue #3) lives here.
