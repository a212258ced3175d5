//! Static equilibrium (`conventions.md`, "Static equilibrium").
pub mod constraint;
pub mod coords;
pub mod error;
pub mod forces;
#[cfg(test)]
mod testkit;
pub mod wrench;
