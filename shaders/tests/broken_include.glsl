// Test-only: a compile error on line 3 of an included file.
float brokenHelper() { return 1.0; }
float brokenLine() { return undeclaredThing; }
