# nvidia-h100-x1, main at c5d92fd's build (serve merged) packed with its libraries in .device/:
OUT=$OUT/serve bash benchmarks/serve_check.sh
