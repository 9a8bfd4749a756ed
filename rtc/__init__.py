"""The ``rtc`` command line: thin wrappers over raytracer/, variants/, steps/ and harness/."""
