// Discrete-time algebraic Riccati equation through SLICOT SB02OD (generalised Schur method).
#pragma once

#include <Eigen/Core>
#include <string>

namespace quadfdi {

struct RiccatiResult {
  Eigen::MatrixXd X;     // stabilising solution of X = AᵀXA − AᵀXB(R+BᵀXB)⁻¹BᵀXA + Q
  double rcond = 0.0;    // SLICOT's reciprocal condition number of the system it solved
  int info = 0;          // SLICOT INFO; 0 = success
  std::string message;   // empty on success, else why it failed
  bool ok() const { return info == 0 && message.empty(); }
};

// Solves the DARE for (A, B, Q, R). Q symmetric ⪰ 0, R symmetric ≻ 0.
RiccatiResult solveDiscreteRiccati(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                                   const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R);

// ‖AᵀXA − X − AᵀXB(R+BᵀXB)⁻¹BᵀXA + Q‖_F / max(1, ‖X‖_F): how well X solves the DARE.
double discreteRiccatiResidual(const Eigen::MatrixXd& A, const Eigen::MatrixXd& B,
                               const Eigen::MatrixXd& Q, const Eigen::MatrixXd& R,
                               const Eigen::MatrixXd& X);

}  // namespace quadfdi
