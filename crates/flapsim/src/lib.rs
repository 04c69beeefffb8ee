//! flapsim
