# Shaders used by the RHI conformance tests (tests/rhi).
