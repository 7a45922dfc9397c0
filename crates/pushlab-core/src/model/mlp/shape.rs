//! The network's shape: the sizes every layer function and the network itself are written for. A leaf,
//! so that the layers (below the network) and the network share it without naming each other.

/// Inputs of the paper's network.
pub const INPUTS: usize = 4;
/// Units in each hidden layer.
pub const HIDDEN: usize = 16;
/// Outputs of the network.
pub const OUTPUTS: usize = 4;
/// Number of weights and biases of the paper's network.
pub const PARAMETER_COUNT: usize = parameter_count(INPUTS);

/// Number of weights and biases of a network with `inputs` inputs.
pub const fn parameter_count(inputs: usize) -> usize {
    inputs * HIDDEN + HIDDEN + 2 * (HIDDEN * HIDDEN + HIDDEN) + HIDDEN * OUTPUTS + OUTPUTS
}
