//! flightlog
