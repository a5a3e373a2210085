//! A resonant stationary noise: the AR(2) process x_k = a₁x_{k−1} + a₂x_{k−2} + u_k, its
//! autocovariance in closed form (the Yule–Walker recursion, Brockwell & Davis, *Time Series:
//! Theory and Methods*, 2nd ed., 1991, §3.3) and its spectrum on Welch bins — the shape of a
//! lightly damped mode's response to white noise, as a force's noise passes through a structure.

/// The AR(2) process of coefficients (a₁, a₂).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ar2 {
    /// a₁.
    pub a1: f64,
    /// a₂.
    pub a2: f64,
}

impl Ar2 {
    /// Poles at radius `r` and angle `omega` (rad per sample): a resonance of damping ratio about
    /// (1 − r)/ω.
    pub fn resonance(r: f64, omega: f64) -> Self {
        Self { a1: 2.0 * r * omega.cos(), a2: -r * r }
    }

    /// γ₀…γ_lags for innovations of variance `s2`: ρ₁ = a₁/(1 − a₂), ρ_l = a₁ρ_{l−1} + a₂ρ_{l−2},
    /// γ₀ = s2/(1 − a₁ρ₁ − a₂ρ₂).
    pub fn autocovariance(&self, lags: usize, s2: f64) -> Vec<f64> {
        let (a1, a2) = (self.a1, self.a2);
        let mut rho = vec![1.0, a1 / (1.0 - a2)];
        for l in 2..=lags.max(2) {
            rho.push(a1 * rho[l - 1] + a2 * rho[l - 2]);
        }
        let g0 = s2 / (1.0 - a1 * rho[1] - a2 * rho[2]);
        rho.truncate(lags + 1);
        rho.iter().map(|r| g0 * r).collect()
    }

    /// The one-sided spectrum on `bins` Welch bins (bin b at π b/bins rad per sample) for
    /// innovations of variance `s2`, with a white floor of level `floor` added: s2/|A(e^{iw})|² +
    /// floor.
    pub fn spectrum(&self, bins: usize, s2: f64, floor: f64) -> Vec<f64> {
        let (a1, a2) = (self.a1, self.a2);
        (0..bins)
            .map(|b| {
                let w = std::f64::consts::PI * b as f64 / bins as f64;
                let (re, im) =
                    (1.0 - a1 * w.cos() - a2 * (2.0 * w).cos(), a1 * w.sin() + a2 * (2.0 * w).sin());
                s2 / (re * re + im * im) + floor
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::Ar2;

    /// The closed-form autocovariance against the inverse transform of the spectrum on a fine
    /// grid (γ_l = (1/π)∫₀^π S(w) cos(lw) dw), and the Yule–Walker equations it satisfies.
    #[test]
    fn the_autocovariance_is_the_spectrums_transform() {
        let p = Ar2::resonance(0.9, 0.6);
        let gamma = p.autocovariance(5, 2.0);
        let bins = 200_000;
        let s = p.spectrum(bins, 2.0, 0.0);
        for (l, g) in gamma.iter().enumerate() {
            let integral: f64 = s
                .iter()
                .enumerate()
                .map(|(b, v)| v * (l as f64 * std::f64::consts::PI * b as f64 / bins as f64).cos())
                .sum::<f64>()
                / bins as f64;
            assert!((integral - g).abs() < 1e-3 * gamma[0], "lag {l}: {integral} against {g}");
        }
        assert!((gamma[0] - p.a1 * gamma[1] - p.a2 * gamma[2] - 2.0).abs() < 1e-9 * gamma[0]);
    }
}
