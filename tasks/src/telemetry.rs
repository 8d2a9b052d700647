//! Telemetry records (being written).
