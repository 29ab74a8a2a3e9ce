# Stand-in for a real-client test whose client is not installed: fails with MSG.
message(FATAL_ERROR "${MSG}")
