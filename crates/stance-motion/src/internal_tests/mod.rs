//! Tests of the pipeline's private stages (the integration tests in `tests/` use the public API
//! only).

mod com_reference;
mod force_check;
