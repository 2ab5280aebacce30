#!/usr/bin/python3
"""The yardstick for bench/training_bench.cpp: the same LSTM/MLP, loss and Adam step in
PyTorch's Python API (Debian's python3-torch, same LibTorch backend). Prints windows/s."""
import sys
import time

import torch

T, N_IN, H, BATCH = 100, 10, 128, 512


class Lstm(torch.nn.Module):
    def __init__(self):
        super().__init__()
        self.lstm = torch.nn.LSTM(N_IN, H, batch_first=True)
        self.head1 = torch.nn.Linear(H, 64)
        self.head2 = torch.nn.Linear(64, 4)

    def forward(self, x):
        out, _ = self.lstm(x)
        return torch.sigmoid(self.head2(torch.relu(self.head1(torch.relu(out[:, -1])))))


def mlp():
    layers = [torch.nn.Linear(N_IN * T, H), torch.nn.ReLU()]
    for _ in range(3):
        layers += [torch.nn.Linear(H, H), torch.nn.ReLU()]
    layers += [torch.nn.Linear(H, 64), torch.nn.ReLU(), torch.nn.Linear(64, 4), torch.nn.Sigmoid()]
    return torch.nn.Sequential(torch.nn.Flatten(), *layers)


def measure(net, threads, seconds):
    torch.set_num_threads(threads)
    opt = torch.optim.Adam(net.parameters(), lr=5e-4, weight_decay=1e-5)
    x, y = torch.randn(BATCH, T, N_IN), torch.rand(BATCH, 4)
    steps, start = 0, time.perf_counter()
    while True:
        opt.zero_grad()
        loss = torch.relu((net(x) - y).norm(dim=1) - 0.01).mean()
        loss.backward()
        opt.step()
        loss.item()
        steps += 1
        elapsed = time.perf_counter() - start
        if elapsed > seconds and steps >= 3:
            return steps * BATCH / elapsed


def main():
    seconds = float(sys.argv[1]) if len(sys.argv) > 1 else 3.0
    torch.manual_seed(0)
    for name, net in (("lstm", Lstm()), ("mlp", mlp())):
        for threads in (1, 2):
            rate = measure(net, threads, seconds)
            print(f"pytorch-python {name} threads={threads} batch={BATCH}: {rate:,.0f} windows/s")


if __name__ == "__main__":
    main()
