// The contact-network solver (issue #5) lives here.
